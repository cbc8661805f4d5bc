#include "odomcal/solver/floor_plane.h"

#include "odomcal/solver/angles.h"
#include "odomcal/solver/floor_translation_z.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace odomcal {
namespace {

// A forward-looking camera (optical z along the robot's x) 0.4 m above a
// floor at z = floor_z, driving a circle of radius 2 m; floor points
// scattered around the path with 3 mm noise, plus clutter above the floor.
struct Scene {
  std::vector<FloorCandidatePoint> points;
  std::vector<FloorCamera> cameras;
  Rigid3d odom_from_cam;
};

Scene MakeScene(double floor_z,
                double slope_deg,
                int num_floor_points,
                bool clutter = true,
                uint64_t seed = 7) {
  Scene scene;
  scene.odom_from_cam.rotation =
      Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5);  // optical, forward
  scene.odom_from_cam.translation = Eigen::Vector3d(0.25, 0.05, 0.0);
  for (int i = 0; i < 60; ++i) {
    const double yaw = 2.0 * M_PI * i / 60.0;
    Rigid3d origin_from_odom(
        Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ())),
        Eigen::Vector3d(2.0 * std::cos(yaw), 2.0 * std::sin(yaw), 0.0));
    scene.cameras.push_back(
        {origin_from_odom * scene.odom_from_cam, i < 30 ? 0 : 1});
  }
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> uniform(-3.5, 3.5);
  std::normal_distribution<double> noise(0.0, 0.003);
  const double slope = std::tan(slope_deg * kDegToRad);
  for (int i = 0; i < num_floor_points; ++i) {
    const double x = uniform(random);
    const double y = uniform(random);
    scene.points.push_back(
        {Eigen::Vector3d(x, y, floor_z + slope * x + noise(random)), 0.003});
  }
  // Clutter: box faces and walls, above the floor.
  for (int i = 0; clutter && i < num_floor_points / 2; ++i) {
    scene.points.push_back(
        {Eigen::Vector3d(uniform(random),
                         uniform(random),
                         floor_z + 0.05 + 0.1 * std::abs(uniform(random))),
         0.003});
  }
  return scene;
}

Eigen::Matrix2d SmallMotionCovariance() {
  const double sigma = 0.05 * kDegToRad;
  return Eigen::Matrix2d::Identity() * sigma * sigma;
}

// The floor of `scene` under `extrinsic`, with two segments of scale 1 and a
// motion whose roll/pitch sigma is 0.05 deg.
FloorPlane Fit(const Scene& scene, const Rigid3d& extrinsic) {
  return FitFloorPlane(scene.points,
                       scene.cameras,
                       extrinsic,
                       SmallMotionCovariance(),
                       {1.0, 1.0},
                       FloorPlaneOptions());
}
FloorPlane Fit(const Scene& scene) { return Fit(scene, scene.odom_from_cam); }

TEST(FloorPlane, LevelFloorGivesTheCameraHeight) {
  const Scene scene = MakeScene(-0.4, 0.0, 2000);
  const FloorPlane floor = Fit(scene);
  ASSERT_EQ(floor.status, FloorPlaneStatus::kFitted) << floor.reason;
  EXPECT_NEAR(floor.camera_height_m, 0.4, 0.001);
  EXPECT_GT(floor.camera_height_stddev_m, 0.0);
  EXPECT_LT(floor.camera_height_stddev_m, 0.001);
  EXPECT_LT(floor.tilt_deg, 0.1);
  EXPECT_NEAR(floor.floor_roll_deg, -90.0, 0.1);
  EXPECT_NEAR(floor.floor_pitch_deg, 0.0, 0.1);
  // Clutter above the floor is not in it.
  EXPECT_LE(floor.num_inliers, 2000);
  EXPECT_GE(floor.num_inliers, 1900);
  // Half the cameras per segment, scale 1: d H / d s_k = H / 2.
  ASSERT_EQ(floor.height_per_scale.size(), 2u);
  EXPECT_NEAR(floor.height_per_scale[0], 0.2, 0.001);
  EXPECT_NEAR(floor.height_per_scale[1], 0.2, 0.001);
}

TEST(FloorPlane, TiltedCameraMountIsSeenInTheFloorsRollAndPitch) {
  Scene scene = MakeScene(-0.4, 0.0, 2000);
  // The motion's extrinsic pitched by 1 deg against the model's cameras:
  // the floor says so, and disagrees beyond the sigmas.
  const Rigid3d wrong(Eigen::Quaterniond(Eigen::AngleAxisd(
                          1.0 * kDegToRad, Eigen::Vector3d::UnitY())) *
                          scene.odom_from_cam.rotation,
                      scene.odom_from_cam.translation);
  const FloorPlane floor = Fit(scene, wrong);
  EXPECT_EQ(floor.status, FloorPlaneStatus::kDisagreesWithMotion);
  EXPECT_NE(floor.reason.find("sloped floor"), std::string::npos);
  EXPECT_NEAR(floor.floor_pitch_deg, 0.0, 0.05);
  EXPECT_NEAR(floor.roll_pitch_correction_rad.norm(),
              1.0 * kDegToRad,
              0.05 * kDegToRad);
}

TEST(FloorPlane, FloorSlopedAgainstTheDrivenPlaneIsNamed) {
  const Scene scene = MakeScene(-0.4, 3.0, 2000);
  const FloorPlane floor = Fit(scene);
  EXPECT_EQ(floor.status, FloorPlaneStatus::kSloped);
  EXPECT_NE(floor.reason.find("tilted 3"), std::string::npos) << floor.reason;
  EXPECT_NEAR(floor.tilt_deg, 3.0, 0.1);
  // Steeper than max_tilt_deg: not the floor at all.
  const Scene steep = MakeScene(-0.4, 20.0, 2000, /*clutter=*/false);
  const FloorPlane none = Fit(steep);
  EXPECT_NE(none.status, FloorPlaneStatus::kFitted);
}

// An untextured floor: no floor points, only the sides of boxes standing on
// it. A level plane slices them, with as many points beside it as on it.
TEST(FloorPlane, LevelSliceThroughVerticalSurfacesIsNotAFloor) {
  Scene scene = MakeScene(-0.4, 0.0, 0, /*clutter=*/false);
  std::mt19937_64 random(3);
  std::uniform_real_distribution<double> along(-0.5, 0.5), up(0.0, 0.35);
  for (int box = 0; box < 6; ++box) {
    const Eigen::Vector2d centre(2.5 * std::cos(box), 2.5 * std::sin(box));
    for (int i = 0; i < 300; ++i) {
      const bool x_face = i % 2 == 0;
      const Eigen::Vector2d xy =
          centre + (x_face ? Eigen::Vector2d(0.5, along(random))
                           : Eigen::Vector2d(along(random), 0.5));
      scene.points.push_back(
          {Eigen::Vector3d(xy.x(), xy.y(), -0.4 + up(random)), 0.003});
    }
  }
  const FloorPlane floor = Fit(scene);
  EXPECT_EQ(floor.status, FloorPlaneStatus::kNotDistinct) << floor.reason;
  EXPECT_NE(floor.reason.find("no plane stands out"), std::string::npos);
}

TEST(FloorPlane, UnseenFloorIsTooFewPoints) {
  const Scene scene = MakeScene(-0.4, 0.0, 20);
  const FloorPlane floor = Fit(scene);
  EXPECT_EQ(floor.status, FloorPlaneStatus::kTooFewPoints);
  EXPECT_NE(floor.reason.find("not seen"), std::string::npos);
}

// A side camera 0.6 m up looking left (yaw 90 deg) and 17 deg down,
// driving 6 m along x. The floor points lie 0.7-3 m beside the path, their
// sigma growing with the square of the distance from the camera that saw
// them (1 mm at 1 m: low resolution, grazing views). A model that bends
// where the views graze: heights beyond 1 m from the camera biased by
// bend_per_m2 times the square of the excess, which tilts the whole floor
// against the cameras by about 0.065 deg per 0.001. A floor sloped by
// slope_deg about x.
Scene MakeFarSideScene(double bend_per_m2,
                       uint64_t seed,
                       double slope_deg = 0.0) {
  Scene scene;
  const Eigen::Quaterniond forward(0.5, -0.5, 0.5, -0.5);  // optical, forward
  scene.odom_from_cam.rotation =
      Eigen::Quaterniond(
          Eigen::AngleAxisd(0.5 * M_PI, Eigen::Vector3d::UnitZ())) *
      Eigen::Quaterniond(
          Eigen::AngleAxisd(17.0 * kDegToRad, Eigen::Vector3d::UnitY())) *
      forward;
  scene.odom_from_cam.translation = Eigen::Vector3d(0.0, 0.15, 0.6);
  std::vector<Eigen::Vector3d> centres;
  for (int i = 0; i < 50; ++i) {
    const Rigid3d origin_from_odom(Eigen::Quaterniond::Identity(),
                                   Eigen::Vector3d(6.0 * i / 49.0, 0.0, 0.0));
    scene.cameras.push_back({origin_from_odom * scene.odom_from_cam, 0});
    centres.push_back(scene.cameras.back().origin_from_cam.translation);
  }
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> along(0.0, 6.0), side(0.7, 3.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int i = 0; i < 1500; ++i) {
    const Eigen::Vector3d on_floor(along(random), 0.15 + side(random), 0.0);
    double distance = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3d& centre : centres) {
      distance = std::min(distance, (on_floor - centre).norm());
    }
    const double sigma = 0.001 * distance * distance;
    FloorCandidatePoint point;
    const double bend =
        bend_per_m2 * std::pow(std::max(0.0, distance - 1.0), 2);
    point.xyz = on_floor +
                Eigen::Vector3d(0.0,
                                0.0,
                                std::tan(slope_deg * kDegToRad) * on_floor.y() +
                                    bend + sigma * normal(random));
    point.sigma_m = sigma;
    point.distance_m = distance;
    scene.points.push_back(point);
  }
  return scene;
}

// The motion's roll/pitch as well known as on the rendered scenes (0.01 deg).
FloorPlane FitTightMotion(const Scene& scene, const Rigid3d& extrinsic) {
  const double sigma = 0.01 * kDegToRad;
  return FitFloorPlane(scene.points,
                       scene.cameras,
                       extrinsic,
                       Eigen::Matrix2d::Identity() * sigma * sigma,
                       {1.0},
                       FloorPlaneOptions());
}

Rigid3d RotatedAboutOdometryX(const Rigid3d& extrinsic, double angle_deg) {
  return Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(
                     angle_deg * kDegToRad, Eigen::Vector3d::UnitX())) *
                     extrinsic.rotation,
                 extrinsic.translation);
}

TEST(FloorPlane, BentFarFloorIsAcceptedWithItsOwnTiltError) {
  for (const uint64_t seed : {1u, 2u, 3u}) {
    const Scene scene = MakeFarSideScene(0.0015, seed);
    const FloorPlane floor = FitTightMotion(scene, scene.odom_from_cam);
    ASSERT_EQ(floor.status, FloorPlaneStatus::kFitted) << floor.reason;
    // The bend tilts the floor against the cameras by more than 0.09 deg:
    // against the motion's 0.01 deg and a fixed 0.02 deg for the model, a
    // chi-square above 14 (refused). The bands near and far disagree, and
    // that measures it.
    EXPECT_GT(floor.roll_pitch_correction_rad.norm() * kRadToDeg, 0.09);
    EXPECT_GT(floor.tilt_band_sigma_rad * kRadToDeg, 0.05);
    EXPECT_EQ(floor.tilt_parts, 12);
    EXPECT_NEAR(floor.camera_height_m, 0.6, 0.005);
    // A 0.5 to 1 deg roll contradiction is still refused.
    for (const double angle_deg : {0.5, -0.5, 1.0}) {
      const FloorPlane wrong = FitTightMotion(
          scene, RotatedAboutOdometryX(scene.odom_from_cam, angle_deg));
      EXPECT_EQ(wrong.status, FloorPlaneStatus::kDisagreesWithMotion)
          << "seed " << seed << ", " << angle_deg << " deg: " << wrong.reason;
    }
    // So is a floor sloped by 0.7 deg under the same model.
    const Scene sloped = MakeFarSideScene(0.0015, seed, 0.7);
    const FloorPlane tilted = FitTightMotion(sloped, sloped.odom_from_cam);
    EXPECT_EQ(tilted.status, FloorPlaneStatus::kSloped) << tilted.reason;
  }
}

TEST(FloorPlane, CleanFarFloorRefusesHalfADegree) {
  const Scene scene = MakeFarSideScene(0.0, 4);
  const FloorPlane floor = FitTightMotion(scene, scene.odom_from_cam);
  ASSERT_EQ(floor.status, FloorPlaneStatus::kFitted) << floor.reason;
  EXPECT_LT(floor.roll_pitch_correction_rad.norm() * kRadToDeg, 0.03);
  EXPECT_LT(floor.tilt_band_sigma_rad * kRadToDeg, 0.03);
  const FloorPlane wrong =
      FitTightMotion(scene, RotatedAboutOdometryX(scene.odom_from_cam, 0.5));
  EXPECT_EQ(wrong.status, FloorPlaneStatus::kDisagreesWithMotion)
      << wrong.reason;
}

// A model that bends so much that the bands near and far disagree by more
// than 0.13 deg: a 0.5 deg slope or roll/pitch error could pass, so z is
// held and the reason says why.
TEST(FloorPlane, FloorTiltTooUncertainToTellHalfADegreeIsNamed) {
  const Scene scene = MakeFarSideScene(0.006, 5);
  const FloorPlane floor = FitTightMotion(scene, scene.odom_from_cam);
  EXPECT_EQ(floor.status, FloorPlaneStatus::kTiltUncertain) << floor.reason;
  EXPECT_NE(floor.reason.find("would pass unseen"), std::string::npos);
  EXPECT_GT(floor.tilt_band_sigma_rad * kRadToDeg, 0.134);
}

TEST(FloorPlane, OptionsAreChecked) {
  FloorPlaneOptions options;
  options.max_tilt_deg = 95.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = FloorPlaneOptions();
  options.min_inliers = 2;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  EXPECT_EQ(FloorPlaneUseFromString("check"), FloorPlaneUse::kCheck);
  EXPECT_THROW(FloorPlaneUseFromString("yes"), std::invalid_argument);
}

TEST(FloorTranslationZ, AppendsZWithTheScalesCovariance) {
  const Scene scene = MakeScene(-0.4, 0.0, 2000);
  const FloorPlane floor = Fit(scene);
  ASSERT_TRUE(floor.Fitted());
  CalibrationResult result;
  result.has_estimate = true;
  result.odom_from_cam = scene.odom_from_cam;
  result.metric_scales = {1.0, 1.0};
  result.observability.metric_scales = {Determination::kEstimated,
                                        Determination::kEstimated};
  result.covariance_segments = {0, 1};
  Eigen::MatrixXd covariance = Eigen::MatrixXd::Identity(7, 7) * 1e-6;
  covariance(5, 5) = 1e-4;  // 1 % scale sigma
  covariance(6, 6) = 4e-4;  // 2 %
  covariance(5, 3) = covariance(3, 5) = 2e-6;
  result.covariance = covariance;
  FloorPlaneOptions options;
  options.odometry_height_m = 0.1;
  EXPECT_EQ(SetTranslationZFromFloor(floor, options, 0.05, &result), "");
  EXPECT_NEAR(result.odom_from_cam.translation.z(), 0.3, 0.001);
  EXPECT_EQ(result.observability.translation_z, Determination::kEstimated);
  EXPECT_EQ(result.observability.translation_z_source,
            TranslationZSource::kFloorPlane);
  ASSERT_EQ(result.covariance->rows(), 8);
  // z = g_0 s_0 + g_1 s_1 + plane (g_k about 0.2).
  const double g0 = floor.height_per_scale[0];
  const double g1 = floor.height_per_scale[1];
  const double expected = g0 * g0 * 1e-4 + g1 * g1 * 4e-4 +
                          std::pow(floor.camera_height_stddev_m, 2);
  EXPECT_NEAR((*result.covariance)(7, 7), expected, 1e-8);
  EXPECT_NEAR((*result.covariance)(7, 3), g0 * 2e-6, 1e-12);
  EXPECT_NEAR(result.stddev_translation_z_m, std::sqrt(expected), 1e-12);
  // A z known only to more than the limit stays held.
  CalibrationResult loose = result;
  loose.observability.translation_z = Determination::kHeld;
  loose.covariance = covariance;
  EXPECT_NE(SetTranslationZFromFloor(floor, options, 1e-4, &loose)
                .find("more than --max_translation_stddev_m"),
            std::string::npos);
  EXPECT_EQ(loose.observability.translation_z, Determination::kHeld);
  // A second call keeps the estimate (z no longer held).
  EXPECT_NE(SetTranslationZFromFloor(floor, options, 0.05, &result), "");
}

TEST(FloorTranslationZ, CheckOnlyKeepsZHeld) {
  const Scene scene = MakeScene(-0.4, 0.0, 2000);
  const FloorPlane floor = Fit(scene);
  CalibrationResult result;
  FloorPlaneOptions options;
  options.use = FloorPlaneUse::kCheck;
  EXPECT_NE(SetTranslationZFromFloor(floor, options, 0.05, &result), "");
  EXPECT_EQ(result.observability.translation_z, Determination::kHeld);
}

}  // namespace
}  // namespace odomcal
