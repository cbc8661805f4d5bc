// The floor under a calibrated project's metric model, fitted a second time
// on the joint adjustment's model where its check agreed: the difference of
// the two camera heights goes into z's standard deviation.

#include "odomcal/plugin/colmap/floor_height.h"

#include "odomcal/adapters/test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace odomcal {
namespace {

constexpr double kCameraHeightM = 0.4;

// A forward-looking camera (optical z along the robot's x) at
// kCameraHeightM, on a robot driving a circle of radius 3 m, over a floor at
// z = floor_z with 1 mm noise; every floor point seen by the two images
// nearest to it (COLMAP's pixel convention does not matter here: the fit
// reads the poses, the points and their tracks).
MetricSubModel FloorModel(double floor_z, const Rigid3d& odom_from_cam) {
  MetricSubModel metric;
  metric.name = "0";
  metric.output_segment = 0;
  ColmapModel& model = metric.model;
  model.cameras[1] = MakeColmapCamera(
      1, ColmapCameraModel::kPinhole, 320, 240, {260.0, 260.0, 160.0, 120.0});
  constexpr int kImages = 72;
  for (int i = 0; i < kImages; ++i) {
    const double yaw = 2.0 * M_PI * i / kImages;
    const Rigid3d origin_from_odom(
        Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ())),
        Eigen::Vector3d(3.0 * std::cos(yaw), 3.0 * std::sin(yaw), 0.0));
    ColmapImage image;
    image.image_id = static_cast<uint32_t>(i + 1);
    image.camera_id = 1;
    image.name = "img" + std::to_string(1000 + i) + ".png";
    image.cam_from_world = Inverse(origin_from_odom * odom_from_cam);
    model.images[image.image_id] = image;
  }
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> radius(1.5, 4.5);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI);
  std::normal_distribution<double> noise(0.0, 0.001);
  for (int p = 0; p < 3000; ++p) {
    const double a = angle(random);
    const double r = radius(random);
    ColmapPoint3D point;
    point.point3D_id = p + 1;
    point.xyz = Eigen::Vector3d(
        r * std::cos(a), r * std::sin(a), floor_z + noise(random));
    point.error = 0.5;
    // The images 5 steps behind and 2 steps behind the point's bearing.
    const int nearest =
        static_cast<int>(std::lround(a / (2.0 * M_PI) * kImages)) % kImages;
    for (const int step : {-5, -2}) {
      const uint32_t id =
          static_cast<uint32_t>((nearest + step + kImages) % kImages + 1);
      ColmapImage& image = model.images.at(id);
      image.points2D.push_back({Eigen::Vector2d(1.0, 1.0), point.point3D_id});
      point.track.push_back(
          {id, static_cast<uint32_t>(image.points2D.size() - 1)});
    }
    model.points3D[point.point3D_id] = point;
  }
  return metric;
}

// A calibration of the drive: rotation and x, y determined with a small
// covariance (order rx, ry, rz, tx, ty, scale), z held at 0.
ColmapCalibrationRun CalibratedRun(const Rigid3d& odom_from_cam) {
  ColmapCalibrationRun run;
  CalibrationResult& result = run.check.result;
  result.has_estimate = true;
  result.odom_from_cam = odom_from_cam;
  result.odom_from_cam.translation.z() = 0.0;
  result.metric_scales = {1.0};
  result.covariance_segments = {0};
  Eigen::VectorXd variances(6);
  const double rotation = std::pow(0.02 * M_PI / 180.0, 2);
  variances << rotation, rotation, rotation, 1e-6, 1e-6, 1e-8;
  result.covariance = Eigen::MatrixXd(variances.asDiagonal());
  result.observability.metric_scales = {Determination::kEstimated};
  run.metric_models.push_back(FloorModel(0.0, odom_from_cam));
  run.joint.result.odom_from_cam = result.odom_from_cam;
  run.joint.result.covariance = result.covariance->topLeftCorner<5, 5>() * 0.25;
  return run;
}

Rigid3d ForwardCamera() {
  return Rigid3d(Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5),
                 Eigen::Vector3d(0.25, 0.05, kCameraHeightM));
}

TEST(FloorHeight, ZFromTheFloorWithoutASecondModel) {
  ColmapCalibrationRun run = CalibratedRun(ForwardCamera());
  ApplyFloorPlane(FloorPlaneOptions(), 0.05, {}, nullptr, &run);
  const CalibrationResult& result = run.check.result;
  ASSERT_TRUE(result.floor_plane.has_value());
  ASSERT_TRUE(result.floor_plane->Fitted()) << result.floor_plane->reason;
  EXPECT_TRUE(std::isnan(result.floor_plane->camera_height_model_difference_m));
  EXPECT_NEAR(result.odom_from_cam.translation.z(), kCameraHeightM, 5e-4);
  EXPECT_LT(result.stddev_translation_z_m, 5e-4);
}

// A COLMAP bundle adjustment that moved fy 18 % from fx (planar motion
// does not fix it; no database: square pixels before) stretched the model's
// vertical: the height's sigma holds that stretch, so z is not set from the
// floor (0.07 m > 0.05 m), and a warning names the aspect; square pixels add
// nothing.
TEST(FloorHeight, AModelWithUnequalFocalLengthsWidensTheHeight) {
  ColmapCalibrationRun square = CalibratedRun(ForwardCamera());
  ApplyFloorPlane(FloorPlaneOptions(), 0.05, {}, nullptr, &square);
  ASSERT_TRUE(square.check.result.floor_plane->Fitted());
  EXPECT_EQ(square.check.result.floor_plane->camera_height_pixel_aspect_m, 0.0);
  EXPECT_EQ(square.check.result.floor_plane->pixel_aspect_change, 1.0);

  ColmapCalibrationRun run = CalibratedRun(ForwardCamera());
  run.metric_models[0].model.cameras.at(1).params = {
      260.0, 220.0, 160.0, 120.0};
  ApplyFloorPlane(FloorPlaneOptions(), 0.05, {}, nullptr, &run);
  const CalibrationResult& result = run.check.result;
  ASSERT_TRUE(result.floor_plane.has_value());
  const FloorPlane& floor = *result.floor_plane;
  ASSERT_TRUE(floor.Fitted()) << floor.reason;
  EXPECT_NEAR(floor.pixel_aspect_change, 260.0 / 220.0, 1e-12);
  EXPECT_NEAR(floor.camera_height_pixel_aspect_m,
              (260.0 / 220.0 - 1.0) * floor.camera_height_m,
              1e-12);
  EXPECT_GE(floor.camera_height_stddev_m, floor.camera_height_pixel_aspect_m);
  EXPECT_EQ(result.odom_from_cam.translation.z(), 0.0);  // held
  EXPECT_NE(result.floor_z_held_reason.find("--max_translation_stddev_m"),
            std::string::npos)
      << result.floor_z_held_reason;
  bool named = false;
  for (const std::string& warning : result.warnings) {
    named = named || warning.find("fx / fy 1.1818 times") != std::string::npos;
  }
  EXPECT_TRUE(named);
}

// The same camera, given so (the database holds fx / fy 260 / 220 before
// the bundle adjustment): nothing moved, nothing added.
TEST(FloorHeight, UnequalFocalLengthsAsGivenAddNothing) {
  ColmapCalibrationRun run = CalibratedRun(ForwardCamera());
  run.metric_models[0].model.cameras.at(1).params = {
      260.0, 220.0, 160.0, 120.0};
  run.metric_models[0].origin_from_sfm = Sim3d();
  run.database_cameras[1] = run.metric_models[0].model.cameras.at(1);
  ApplyFloorPlane(FloorPlaneOptions(), 0.05, {}, nullptr, &run);
  const FloorPlane& floor = *run.check.result.floor_plane;
  ASSERT_TRUE(floor.Fitted()) << floor.reason;
  EXPECT_EQ(floor.pixel_aspect_change, 1.0);
  EXPECT_EQ(floor.camera_height_pixel_aspect_m, 0.0);
  EXPECT_NEAR(
      run.check.result.odom_from_cam.translation.z(), kCameraHeightM, 5e-4);
}

TEST(FloorHeight, TheAgreeingModelsOtherHeightWidensZ) {
  const Rigid3d odom_from_cam = ForwardCamera();
  ColmapCalibrationRun run = CalibratedRun(odom_from_cam);
  // The adjustment's model puts the floor 4 mm lower: the camera 4 mm higher.
  const MetricSubModel joint_model = FloorModel(-0.004, odom_from_cam);
  ApplyFloorPlane(FloorPlaneOptions(), 0.05, {}, &joint_model, &run);
  const CalibrationResult& result = run.check.result;
  ASSERT_TRUE(result.floor_plane.has_value());
  ASSERT_TRUE(result.floor_plane->Fitted()) << result.floor_plane->reason;
  const FloorPlane& floor = *result.floor_plane;
  EXPECT_NEAR(floor.camera_height_model_difference_m, 0.004, 3e-4);
  // z stays the reported model's; its sigma holds the difference.
  EXPECT_NEAR(result.odom_from_cam.translation.z(), kCameraHeightM, 5e-4);
  EXPECT_GE(floor.camera_height_stddev_m,
            std::abs(floor.camera_height_model_difference_m));
  EXPECT_GE(result.stddev_translation_z_m, floor.camera_height_stddev_m);
  EXPECT_LT(result.stddev_translation_z_m, 0.005);
}

TEST(FloorHeight, AFloorTheSecondModelDoesNotShowLeavesZAsItIs) {
  const Rigid3d odom_from_cam = ForwardCamera();
  ColmapCalibrationRun without = CalibratedRun(odom_from_cam);
  ApplyFloorPlane(FloorPlaneOptions(), 0.05, {}, nullptr, &without);
  ColmapCalibrationRun run = CalibratedRun(odom_from_cam);
  MetricSubModel empty = FloorModel(0.0, odom_from_cam);
  empty.model.points3D.clear();
  ApplyFloorPlane(FloorPlaneOptions(), 0.05, {}, &empty, &run);
  ASSERT_TRUE(run.check.result.floor_plane->Fitted());
  EXPECT_TRUE(std::isnan(
      run.check.result.floor_plane->camera_height_model_difference_m));
  EXPECT_EQ(run.check.result.stddev_translation_z_m,
            without.check.result.stddev_translation_z_m);
}

}  // namespace
}  // namespace odomcal
