#include "odomcal/solver/joint_adjustment.h"

#include "odomcal/datasets/simulation/joint_scene.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/camera_intrinsics_manifold.h"
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

// The scenes of datasets/simulation/joint_scene.h: 80 images.
JointScene MakeScene(unsigned seed,
                     double pixel_sigma,
                     double drift,
                     double outlier_fraction = 0.0,
                     double image_shift_px = 0.0) {
  JointSceneOptions options;
  options.seed = seed;
  options.pixel_sigma = pixel_sigma;
  options.drift = drift;
  options.outlier_fraction = outlier_fraction;
  options.image_shift_px = image_shift_px;
  return SimulateJointScene(options);
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
  const JointScene scene = MakeScene(1, 0.5, 0.05);
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
    worst = std::max(
        worst,
        (result.origin_from_odom[i].translation - scene.poses[i].translation)
            .head<2>()
            .norm());
  }
  EXPECT_LT(worst, 0.05);
  EXPECT_LT(result.reprojection_rms_px_after,
            result.reprojection_rms_px_before);
  EXPECT_GT(result.odometry_rms_sigma_after, 0.5);
  EXPECT_LT(result.odometry_rms_sigma_after, 1.5);
}

TEST(AdjustJointly, LeavesOutGrossOutliers) {
  const JointScene scene = MakeScene(2, 0.5, 0.02, 0.02);
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
  JointScene scene = MakeScene(5, 0.5, 0.0);
  JointAdjustmentProblem& problem = scene.problem;
  // 3 m behind the first camera, "seen" by the first two images.
  const Rigid3d origin_from_cam =
      problem.images[0].origin_from_odom * problem.odom_from_cam;
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

TEST(AdjustJointly, LeavesOutAPointSeenAlongParallelRays) {
  JointScene scene = MakeScene(6, 0.5, 0.0);
  JointAdjustmentProblem& problem = scene.problem;
  // 5 km ahead of the first two images, a few decimetres apart: their rays
  // meet at thousandths of a degree, and the point's depth rests on the
  // pixel noise alone.
  const Rigid3d origin_from_cam =
      problem.images[0].origin_from_odom * problem.odom_from_cam;
  problem.points.push_back(origin_from_cam * Eigen::Vector3d(0.0, 0.0, 5000.0));
  const int far = static_cast<int>(problem.points.size()) - 1;
  for (int image = 0; image < 2; ++image) {
    const Rigid3d cam_from_origin =
        Inverse(problem.images[image].origin_from_odom * problem.odom_from_cam);
    const Eigen::Vector3d in_cam = cam_from_origin * problem.points[far];
    Eigen::Vector2d pixel;
    ASSERT_TRUE(ProjectToPixel<ProjectionModel::kSimpleRadial>(
        problem.cameras[0].params.data(), in_cam.data(), pixel.data()));
    problem.observations.push_back({image, far, pixel});
  }
  const JointAdjustmentResult result =
      AdjustJointly(problem, JointAdjustmentOptions());
  ASSERT_TRUE(result.IsSuccess()) << result.message;
  EXPECT_EQ(result.observation_error_px.back(), -1.0);
  JointAdjustmentOptions every_point;
  every_point.min_triangulation_angle_deg = 0.0;
  const JointAdjustmentResult with_it = AdjustJointly(problem, every_point);
  ASSERT_TRUE(with_it.IsSuccess()) << with_it.message;
  EXPECT_GE(with_it.observation_error_px.back(), 0.0);
}

TEST(AdjustJointly, RefinesTheFocalLengthAndHoldsThePrincipalPoint) {
  JointScene scene = MakeScene(7, 0.5, 0.0);
  JointAdjustmentProblem& problem = scene.problem;
  ASSERT_EQ(problem.cameras[0].model, ProjectionModel::kSimpleRadial);
  const std::vector<double> truth = problem.cameras[0].params;
  problem.cameras[0].params[0] *= 1.01;  // f 1 % long
  JointAdjustmentOptions options;
  options.refine_intrinsics = true;
  const JointAdjustmentResult result = AdjustJointly(problem, options);
  ASSERT_TRUE(result.IsSuccess()) << result.message;
  const std::vector<double>& refined = result.cameras[0].params;
  EXPECT_LT(std::abs(refined[0] - truth[0]), 0.2 * 0.01 * truth[0]);
  EXPECT_EQ(refined[1], truth[1]);  // cx, cy: COLMAP's bundle adjustment
  EXPECT_EQ(refined[2], truth[2]);  // holds them too
}

TEST(CameraIntrinsicsManifold,
     ScalesBothFocalLengthsAndHoldsThePrincipalPoint) {
  const internal::CameraIntrinsicsManifold opencv(ProjectionModel::kOpenCV);
  ASSERT_EQ(opencv.AmbientSize(), 8);
  ASSERT_EQ(opencv.TangentSize(), 5);  // focal scale, k1, k2, p1, p2
  const double x[8] = {500.0, 400.0, 320.5, 240.5, -0.1, 0.01, 0.001, 0.002};
  const double delta[5] = {0.02, 0.01, -0.005, 0.0001, -0.0002};
  double moved[8];
  ASSERT_TRUE(opencv.Plus(x, delta, moved));
  EXPECT_DOUBLE_EQ(moved[0] / moved[1], x[0] / x[1]);  // aspect kept
  EXPECT_DOUBLE_EQ(moved[0], x[0] * 1.02);
  EXPECT_EQ(moved[2], x[2]);
  EXPECT_EQ(moved[3], x[3]);
  EXPECT_DOUBLE_EQ(moved[5], x[5] - 0.005);
  double back[5];
  ASSERT_TRUE(opencv.Minus(moved, x, back));
  for (int k = 0; k < 5; ++k) EXPECT_NEAR(back[k], delta[k], 1e-15);
  // The Jacobians against central differences of Plus and Minus at 0.
  double plus_jacobian[8 * 5];
  double minus_jacobian[5 * 8];
  ASSERT_TRUE(opencv.PlusJacobian(x, plus_jacobian));
  ASSERT_TRUE(opencv.MinusJacobian(x, minus_jacobian));
  constexpr double kStep = 1e-7;
  for (int j = 0; j < 5; ++j) {
    double step[5] = {0.0, 0.0, 0.0, 0.0, 0.0};
    step[j] = kStep;
    double ahead[8], behind[8];
    opencv.Plus(x, step, ahead);
    step[j] = -kStep;
    opencv.Plus(x, step, behind);
    for (int k = 0; k < 8; ++k) {
      EXPECT_NEAR(plus_jacobian[k * 5 + j],
                  (ahead[k] - behind[k]) / (2.0 * kStep),
                  1e-6 * (1.0 + std::abs(x[k])));
    }
  }
  double product[5 * 5] = {};
  for (int r = 0; r < 5; ++r) {
    for (int c = 0; c < 5; ++c) {
      for (int k = 0; k < 8; ++k) {
        product[r * 5 + c] +=
            minus_jacobian[r * 8 + k] * plus_jacobian[k * 5 + c];
      }
      EXPECT_NEAR(product[r * 5 + c], r == c ? 1.0 : 0.0, 1e-12);
    }
  }
  const internal::CameraIntrinsicsManifold pinhole(
      ProjectionModel::kSimplePinhole);
  EXPECT_EQ(pinhole.TangentSize(), 1);
}

TEST(AdjustJointly, RefusesImagesWithoutAnOdometryLink) {
  JointScene scene = MakeScene(3, 0.5, 0.0);
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
  JointScene scene = MakeScene(4, 0.5, 0.0);
  scene.problem.links[3].covariance.setZero();
  EXPECT_EQ(AdjustJointly(scene.problem, JointAdjustmentOptions()).status,
            JointAdjustmentStatus::kInvalidInput);
  JointAdjustmentOptions options;
  options.pixel_sigma = 0.0;
  EXPECT_THROW(AdjustJointly(MakeScene(4, 0.5, 0.0).problem, options),
               std::invalid_argument);
  options = JointAdjustmentOptions();
  options.min_triangulation_angle_deg = 90.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
}

// The images in time order, as the problem lists them.
std::vector<int> InOrder(const JointAdjustmentProblem& problem) {
  std::vector<int> order(problem.images.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  return order;
}

TEST(JackknifeJointExtrinsic, AgreesWithTheModelWhereItsNoiseIsRight) {
  const JointScene scene = MakeScene(2, 0.5, 0.05);
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
    // Never narrowed (up to the rounding of undoing and redoing the
    // model's widening).
    EXPECT_GE(result.covariance(k, k), before(k, k) * (1.0 - 1e-12));
  }
}

TEST(JackknifeJointExtrinsic, WidensWhatErrorsCommonToAnImageHide) {
  // Each image's features move together by 0.6 px besides their own
  // 0.3 px: the model (and the per-track sandwich) count 0.3 px
  // independent errors and understate the extrinsic's spread.
  const JointScene scene = MakeScene(3, 0.3, 0.05, 0.0, 0.6);
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
  const JointScene scene = MakeScene(4, 0.5, 0.0);
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
