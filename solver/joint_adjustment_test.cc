#include "odomcal/solver/joint_adjustment.h"

#include "odomcal/solver/angles.h"
#include "odomcal/solver/joint_adjustment_jackknife.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace odomcal {
namespace {

TEST(Project, FollowsColmapsModels) {
  const double point[3] = {1.0, 2.0, 4.0};  // u = 0.25, v = 0.5, r^2 = 0.3125
  double pixel[2];
  const double simple_radial[4] = {100.0, 50.0, 40.0, 0.1};
  ASSERT_TRUE(ProjectToPixel<ProjectionModel::kSimpleRadial>(
      simple_radial, point, pixel));
  EXPECT_DOUBLE_EQ(pixel[0], 100.0 * 0.25 * 1.03125 + 50.0);
  EXPECT_DOUBLE_EQ(pixel[1], 100.0 * 0.5 * 1.03125 + 40.0);
  // OPENCV, tangential only: du = 2 p1 u v + p2 (r^2 + 2 u^2).
  const double opencv[8] = {100.0, 200.0, 50.0, 40.0, 0.0, 0.0, 0.01, 0.02};
  ASSERT_TRUE(ProjectToPixel<ProjectionModel::kOpenCV>(opencv, point, pixel));
  EXPECT_DOUBLE_EQ(pixel[0],
                   100.0 * (0.25 + 2 * 0.01 * 0.125 + 0.02 * 0.4375) + 50.0);
  EXPECT_DOUBLE_EQ(pixel[1],
                   200.0 * (0.5 + 2 * 0.02 * 0.125 + 0.01 * 0.8125) + 40.0);
  const double behind[3] = {1.0, 2.0, -4.0};
  EXPECT_FALSE(ProjectToPixel<ProjectionModel::kSimpleRadial>(
      simple_radial, behind, pixel));
}

// A planar drive past random points, observed by a forward camera, with
// wheel odometry between consecutive images, and starting values with a
// COLMAP-like scale drift (the model's size grows along the drive).
struct Scene {
  JointAdjustmentProblem problem;
  Rigid3d odom_from_cam;
  std::vector<PlanarPose> poses;
  std::vector<Eigen::Vector3d> points;
};

Scene MakeScene(int seed,
                double pixel_sigma,
                double drift,
                double outlier_fraction = 0.0,
                double image_shift_px = 0.0) {
  std::mt19937 random(seed);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  Scene scene;
  scene.odom_from_cam.rotation =
      Eigen::AngleAxisd(3.0 * kDegToRad, Eigen::Vector3d::UnitZ()) *
      Eigen::AngleAxisd(-2.0 * kDegToRad, Eigen::Vector3d::UnitY()) *
      Eigen::AngleAxisd(1.0 * kDegToRad, Eigen::Vector3d::UnitX()) *
      Eigen::Quaterniond(
          (Eigen::Matrix3d() << 0, 0, 1, -1, 0, 0, 0, -1, 0).finished());
  scene.odom_from_cam.translation = Eigen::Vector3d(0.3, -0.05, 0.5);
  // 80 images, 0.25 m apart, turning both ways.
  constexpr int kNumImages = 80;
  PlanarPose pose;
  for (int i = 0; i < kNumImages; ++i) {
    scene.poses.push_back(pose);
    const double turn = 0.25 * std::sin(0.12 * i);
    pose.x += 0.25 * std::cos(pose.yaw_rad + 0.5 * turn);
    pose.y += 0.25 * std::sin(pose.yaw_rad + 0.5 * turn);
    pose.yaw_rad += turn;
  }
  // Points 2-8 m to the sides and ahead of the path.
  for (const PlanarPose& p : scene.poses) {
    for (int k = 0; k < 12; ++k) {
      const double ahead = 1.0 + 6.0 * uniform(random);
      const double side = (uniform(random) - 0.5) * 10.0;
      const double height = -0.3 + 2.5 * uniform(random);
      const Eigen::Vector3d in_odom(ahead, side, height);
      scene.points.push_back(p.ToRigid3d() * in_odom);
    }
  }
  JointAdjustmentProblem& problem = scene.problem;
  problem.cameras.push_back(
      {ProjectionModel::kSimpleRadial, {500.0, 320.5, 240.5, -0.05}});
  // Starting values: the drive's size grows by `drift` from its start to
  // its end, as COLMAP's scale drifts; the extrinsic 0.5 deg and 2 cm off.
  const auto drifted = [&](const Eigen::Vector3d& x, double fraction) {
    return Eigen::Vector3d(x.x() * (1.0 + drift * fraction),
                           x.y() * (1.0 + drift * fraction),
                           x.z());
  };
  for (int i = 0; i < kNumImages; ++i) {
    const double fraction = static_cast<double>(i) / kNumImages;
    const Eigen::Vector3d xy = drifted(
        Eigen::Vector3d(scene.poses[i].x, scene.poses[i].y, 0.0), fraction);
    problem.images.push_back(
        {0, {xy.x(), xy.y(), scene.poses[i].yaw_rad + 0.002 * normal(random)}});
  }
  for (size_t k = 0; k < scene.points.size(); ++k) {
    const double fraction =
        static_cast<double>(k / 12) / static_cast<double>(kNumImages);
    problem.points.push_back(
        drifted(scene.points[k], fraction) +
        0.01 * Eigen::Vector3d(normal(random), normal(random), normal(random)));
  }
  problem.odom_from_cam.rotation =
      Eigen::AngleAxisd(0.5 * kDegToRad,
                        Eigen::Vector3d(1.0, -1.0, 1.0).normalized()) *
      scene.odom_from_cam.rotation;
  problem.odom_from_cam.translation =
      scene.odom_from_cam.translation + Eigen::Vector3d(0.02, -0.01, 0.0);
  // Observations within the 640 x 480 image, 0.5 to 12 m ahead.
  const std::vector<double>& params = problem.cameras[0].params;
  for (int i = 0; i < kNumImages; ++i) {
    const Rigid3d cam_from_origin =
        Inverse(scene.poses[i].ToRigid3d() * scene.odom_from_cam);
    // One error common to the image's features (as a timing or rolling
    // shutter error moves them together), which no per-track model sees.
    const Eigen::Vector2d image_shift =
        image_shift_px * Eigen::Vector2d(normal(random), normal(random));
    for (size_t k = 0; k < scene.points.size(); ++k) {
      const Eigen::Vector3d in_cam = cam_from_origin * scene.points[k];
      if (in_cam.z() < 0.5 || in_cam.z() > 12.0) continue;
      Eigen::Vector2d pixel;
      if (!ProjectToPixel<ProjectionModel::kSimpleRadial>(
              params.data(), in_cam.data(), pixel.data()) ||
          pixel.x() < 0.0 || pixel.x() > 640.0 || pixel.y() < 0.0 ||
          pixel.y() > 480.0) {
        continue;
      }
      pixel += image_shift +
               pixel_sigma * Eigen::Vector2d(normal(random), normal(random));
      if (uniform(random) < outlier_fraction) {
        pixel += Eigen::Vector2d(40.0 * normal(random), 40.0 * normal(random));
      }
      problem.observations.push_back({i, static_cast<int>(k), pixel});
    }
  }
  // Odometry between consecutive images: 2 mm + 1 % per axis, 0.2 deg + 1 %.
  for (int i = 0; i + 1 < kNumImages; ++i) {
    const Rigid3d truth =
        Inverse(scene.poses[i].ToRigid3d()) * scene.poses[i + 1].ToRigid3d();
    const PlanarPose motion = PlanarFromRigid(truth);
    const double length = std::hypot(motion.x, motion.y);
    const double xy_sigma = 0.002 + 0.01 * length;
    const double yaw_sigma = 0.2 * kDegToRad + 0.01 * std::abs(motion.yaw_rad);
    OdometryLink link;
    link.image_i = i;
    link.image_j = i + 1;
    link.covariance =
        Eigen::Vector3d(
            xy_sigma * xy_sigma, xy_sigma * xy_sigma, yaw_sigma * yaw_sigma)
            .asDiagonal();
    link.odom_i_from_odom_j = {motion.x + xy_sigma * normal(random),
                               motion.y + xy_sigma * normal(random),
                               motion.yaw_rad + yaw_sigma * normal(random)};
    problem.links.push_back(link);
  }
  // The gauge image starts at its true pose, as the caller's first image
  // starts at its odometry pose.
  problem.images[0].origin_from_odom = scene.poses[0];
  return scene;
}

// Rotation error (rad, about the odometry axes) and x/y error (m) of the
// result, as the covariance orders them.
Eigen::Matrix<double, 5, 1> ExtrinsicError(const JointAdjustmentResult& result,
                                           const Rigid3d& truth) {
  Eigen::Matrix<double, 5, 1> error;
  error.head<3>() =
      LogRotation(result.odom_from_cam.rotation * truth.rotation.conjugate());
  error.tail<2>() =
      (result.odom_from_cam.translation - truth.translation).head<2>();
  return error;
}

TEST(AdjustJointly, RemovesTheModelsScaleDriftAndStatesItsUncertainty) {
  const Scene scene = MakeScene(1, 0.5, 0.05);
  const JointAdjustmentResult result =
      AdjustJointly(scene.problem, JointAdjustmentOptions());
  ASSERT_TRUE(result.IsSuccess()) << result.message;
  EXPECT_EQ(result.num_components, 1);
  EXPECT_NEAR(result.pixel_sigma, 0.5, 0.05);
  EXPECT_EQ(result.odom_from_cam.translation.z(), 0.5);  // held
  const Eigen::Matrix<double, 5, 1> error =
      ExtrinsicError(result, scene.odom_from_cam);
  for (int k = 0; k < 5; ++k) {
    const double sigma = std::sqrt(result.covariance(k, k));
    EXPECT_GT(sigma, 0.0);
    EXPECT_LT(std::abs(error[k]), 4.0 * sigma) << "component " << k;
  }
  // Stated: tenths of a degree and millimetres, not metres.
  EXPECT_LT(std::sqrt(result.covariance(2, 2)), 0.3 * kDegToRad);
  EXPECT_LT(std::sqrt(result.covariance(3, 3)), 0.01);
  // The drift (5 % at the end, about 1 m) is gone from the poses.
  double worst = 0.0;
  for (size_t i = 0; i < scene.poses.size(); ++i) {
    worst =
        std::max(worst,
                 std::hypot(result.origin_from_odom[i].x - scene.poses[i].x,
                            result.origin_from_odom[i].y - scene.poses[i].y));
  }
  EXPECT_LT(worst, 0.05);
  EXPECT_LT(result.reprojection_rms_px_after,
            result.reprojection_rms_px_before);
  EXPECT_GT(result.odometry_rms_sigma_after, 0.5);
  EXPECT_LT(result.odometry_rms_sigma_after, 1.5);
}

TEST(AdjustJointly, LeavesOutGrossOutliers) {
  const Scene scene = MakeScene(2, 0.5, 0.02, 0.02);
  const JointAdjustmentResult result =
      AdjustJointly(scene.problem, JointAdjustmentOptions());
  ASSERT_TRUE(result.IsSuccess()) << result.message;
  EXPECT_GT(result.num_observations_left_out,
            static_cast<int>(0.01 * scene.problem.observations.size()));
  EXPECT_NEAR(result.pixel_sigma, 0.5, 0.075);
  const Eigen::Matrix<double, 5, 1> error =
      ExtrinsicError(result, scene.odom_from_cam);
  for (int k = 0; k < 5; ++k) {
    EXPECT_LT(std::abs(error[k]), 4.0 * std::sqrt(result.covariance(k, k)))
        << "component " << k;
  }
}

TEST(AdjustJointly, LeavesOutAPointBehindItsCameras) {
  Scene scene = MakeScene(5, 0.5, 0.0);
  JointAdjustmentProblem& problem = scene.problem;
  // 3 m behind the first camera, "seen" by the first two images.
  const Rigid3d origin_from_cam =
      problem.images[0].origin_from_odom.ToRigid3d() * problem.odom_from_cam;
  problem.points.push_back(origin_from_cam * Eigen::Vector3d(0.0, 0.0, -3.0));
  const int behind = static_cast<int>(problem.points.size()) - 1;
  problem.observations.push_back({0, behind, Eigen::Vector2d(320.0, 240.0)});
  problem.observations.push_back({1, behind, Eigen::Vector2d(321.0, 240.0)});
  const JointAdjustmentResult result =
      AdjustJointly(problem, JointAdjustmentOptions());
  ASSERT_TRUE(result.IsSuccess()) << result.message;
  EXPECT_GE(result.num_observations_left_out, 2);
  EXPECT_EQ(result.observation_error_px.back(), -1.0);
}

TEST(AdjustJointly, RefusesImagesWithoutAnOdometryLink) {
  Scene scene = MakeScene(3, 0.5, 0.0);
  // Cut the drive in two: no link between the halves, and no point seen
  // from both: the second half's scale is free, and the adjustment must say
  // so rather than return it.
  JointAdjustmentProblem& problem = scene.problem;
  const int half = static_cast<int>(problem.images.size()) / 2;
  std::vector<OdometryLink> first_half;
  for (const OdometryLink& link : problem.links) {
    if (link.image_j < half) first_half.push_back(link);
  }
  problem.links = first_half;
  std::vector<JointObservation> kept;
  for (const JointObservation& observation : problem.observations) {
    const int owner = observation.point / 12;  // the image it was made at
    if ((owner < half) == (observation.image < half))
      kept.push_back(observation);
  }
  problem.observations = kept;
  const JointAdjustmentResult cut =
      AdjustJointly(problem, JointAdjustmentOptions());
  EXPECT_EQ(cut.status, JointAdjustmentStatus::kInvalidInput);
  EXPECT_NE(cut.message.find("no odometry link"), std::string::npos)
      << cut.message;
}

TEST(AdjustJointly, RefusesInvalidInput) {
  Scene scene = MakeScene(4, 0.5, 0.0);
  scene.problem.links[3].covariance.setZero();
  EXPECT_EQ(AdjustJointly(scene.problem, JointAdjustmentOptions()).status,
            JointAdjustmentStatus::kInvalidInput);
  JointAdjustmentOptions options;
  options.pixel_sigma = 0.0;
  EXPECT_THROW(AdjustJointly(MakeScene(4, 0.5, 0.0).problem, options),
               std::invalid_argument);
}

// The images in time order, as the problem lists them.
std::vector<int> InOrder(const JointAdjustmentProblem& problem) {
  std::vector<int> order(problem.images.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  return order;
}

TEST(JackknifeJointExtrinsic, AgreesWithTheModelWhereItsNoiseIsRight) {
  const Scene scene = MakeScene(2, 0.5, 0.05);
  JointAdjustmentOptions options;
  int num_calls = 0;
  int last_pass = 0;
  std::vector<int> replicates_heard;
  options.progress = [&](const JointAdjustmentProgress& where) {
    ++num_calls;
    last_pass = std::max(last_pass, where.pass);
    if (where.num_replicates > 0 &&
        (replicates_heard.empty() ||
         replicates_heard.back() != where.replicate)) {
      EXPECT_EQ(where.num_replicates, 8);
      replicates_heard.push_back(where.replicate);
    }
  };
  JointAdjustmentResult result = AdjustJointly(scene.problem, options);
  EXPECT_GT(num_calls, 2);
  EXPECT_GE(last_pass, 2);  // the pixel sigma is estimated, then solved at
  EXPECT_TRUE(replicates_heard.empty());
  ASSERT_TRUE(result.IsSuccess()) << result.message;
  const Eigen::Matrix<double, 5, 5> before = result.covariance;
  const JointJackknife jackknife = JackknifeJointExtrinsic(
      scene.problem, options, InOrder(scene.problem), {}, &result);
  ASSERT_TRUE(jackknife.ran) << jackknife.reason;
  EXPECT_EQ(jackknife.num_blocks, 8);
  EXPECT_EQ(replicates_heard, std::vector<int>({1, 2, 3, 4, 5, 6, 7, 8}));
  for (int k = 0; k < 5; ++k) {
    // 7 degrees of freedom, and the jackknife errs wide (Efron & Stein):
    // a standard deviation within about -60 % / +150 %.
    EXPECT_GT(jackknife.ratio[k], 0.4) << "component " << k;
    EXPECT_LT(jackknife.ratio[k], 2.5) << "component " << k;
    EXPECT_GE(result.covariance(k, k), before(k, k));
  }
}

TEST(JackknifeJointExtrinsic, WidensWhatErrorsCommonToAnImageHide) {
  // Each image's features move together by 0.6 px besides their own
  // 0.3 px: the model (and the per-track sandwich) count 0.3 px
  // independent errors and understate the extrinsic's spread.
  const Scene scene = MakeScene(3, 0.3, 0.05, 0.0, 0.6);
  const JointAdjustmentOptions options;
  JointAdjustmentResult result = AdjustJointly(scene.problem, options);
  ASSERT_TRUE(result.IsSuccess()) << result.message;
  const Eigen::Matrix<double, 5, 1> error =
      ExtrinsicError(result, scene.odom_from_cam);
  const Eigen::Matrix<double, 5, 1> model_sigma =
      result.covariance.diagonal().cwiseSqrt().cwiseQuotient(
          result.covariance_widening);
  const JointJackknife jackknife = JackknifeJointExtrinsic(
      scene.problem, options, InOrder(scene.problem), {}, &result);
  ASSERT_TRUE(jackknife.ran) << jackknife.reason;
  EXPECT_GT(jackknife.ratio.maxCoeff(), 2.0);
  int outside_model = 0;
  for (int k = 0; k < 5; ++k) {
    if (std::abs(error[k]) > 3.0 * model_sigma[k]) ++outside_model;
    EXPECT_LT(std::abs(error[k]), 3.0 * std::sqrt(result.covariance(k, k)))
        << "component " << k;
  }
  EXPECT_GT(outside_model, 0);  // the case the jackknife is for
}

TEST(JackknifeJointExtrinsic, NeedsTwoImagesPerBlock) {
  const Scene scene = MakeScene(4, 0.5, 0.0);
  JointAdjustmentResult result =
      AdjustJointly(scene.problem, JointAdjustmentOptions());
  ASSERT_TRUE(result.IsSuccess()) << result.message;
  const Eigen::Matrix<double, 5, 5> before = result.covariance;
  JointJackknifeOptions jackknife;
  jackknife.num_blocks = 50;  // 80 images
  const JointJackknife out = JackknifeJointExtrinsic(scene.problem,
                                                     JointAdjustmentOptions(),
                                                     InOrder(scene.problem),
                                                     jackknife,
                                                     &result);
  EXPECT_FALSE(out.ran);
  EXPECT_NE(out.reason.find("fewer than 2 per block"), std::string::npos);
  EXPECT_EQ(result.covariance, before);
  jackknife.num_blocks = 2;
  EXPECT_THROW(jackknife.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace odomcal
