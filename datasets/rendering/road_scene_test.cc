#include "odomcal/datasets/rendering/road_scene.h"

#include "odomcal/datasets/rendering/dataset_presets.h"
#include "odomcal/datasets/rendering/rendered_dataset.h"
#include "odomcal/solver/angles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace odomcal {
namespace {

constexpr double kDeg = M_PI / 180.0;

// Roll and pitch of a car pose: the angles of its up axis from vertical,
// across and along its heading.
Eigen::Vector2d RollPitchDeg(const Rigid3d& room_from_odom) {
  const Eigen::Matrix3d r = room_from_odom.rotation.toRotationMatrix();
  const double pitch = std::asin(std::clamp(-r(2, 0), -1.0, 1.0));
  const double roll = std::atan2(r(2, 1), r(2, 2));
  return Eigen::Vector2d(roll, pitch) / kDeg;
}

TEST(RoadScene, RouteTurnsLeftThenRightAndEndsParallel) {
  const RoadOptions options;
  const std::vector<RoutePiece> route = RoadRoute(options);
  ASSERT_EQ(route.size(), 5u);
  EXPECT_GT(route[1].curvature, 0.0);  // left
  EXPECT_LT(route[3].curvature, 0.0);  // right
  EXPECT_NEAR(route[2].start.yaw_rad, options.left_turn_deg * kDeg, 1e-9);
  EXPECT_NEAR(route[4].start.yaw_rad,
              (options.left_turn_deg - options.right_turn_deg) * kDeg,
              1e-9);
  // The path follows the route at the speed: 2 s in, 14 m along x.
  const UnicyclePath path = MakeRoadPath(options, 5.0);
  const PlanarPose at_2s = path.PoseAt(2000000000);
  EXPECT_NEAR(at_2s.x, 2.0 * options.speed_mps, 1e-6);
  EXPECT_NEAR(at_2s.y, 0.0, 1e-9);
  EXPECT_THROW(MakeRoadPath(options, 1000.0), std::invalid_argument);
}

TEST(RoadScene, FlatGroundKeepsTheCarLevel) {
  const RoadGround ground = MakeRoadGround(RoadOptions());
  for (const double x : {-20.0, 0.0, 33.3, 70.0}) {
    const Eigen::Vector2d p(x, 0.5 * x);
    EXPECT_EQ(ground.Height(p), 0.0);
    const Rigid3d pose = PoseOnGround(ground, {p.x(), p.y(), 0.7});
    EXPECT_NEAR(RotationAngle(pose.rotation.conjugate() *
                              Eigen::Quaterniond(Eigen::AngleAxisd(
                                  0.7, Eigen::Vector3d::UnitZ()))),
                0.0,
                1e-12);
  }
}

// Sloped ground: continuous, its slopes reach (but stay within) the
// amplitudes, and a car on it pitches with the slope along its heading and
// banks with the slope across it.
TEST(RoadScene, SlopedGroundPitchesAndBanksTheCar) {
  RoadOptions options;
  options.slope_x_deg = 2.5;
  options.slope_y_deg = 2.0;
  const RoadGround ground = MakeRoadGround(options);
  double max_x = 0.0, max_y = 0.0;
  const Eigen::Vector2d lo = ground.min_xy(), hi = ground.max_xy();
  for (double x = lo.x() + 0.1; x < hi.x(); x += 0.7) {
    for (double y = lo.y() + 0.1; y < hi.y(); y += 0.7) {
      const Eigen::Vector2d p(x, y);
      const Eigen::Vector2d slope = ground.Gradient(p);
      max_x = std::max(max_x, std::abs(std::atan(slope.x())) / kDeg);
      max_y = std::max(max_y, std::abs(std::atan(slope.y())) / kDeg);
      // Continuity: the height follows the slope between nearby points in
      // the same cell, and across cell borders it does not jump.
      const Eigen::Vector2d q = p + Eigen::Vector2d(0.01, 0.01);
      EXPECT_NEAR(ground.Height(q) - ground.Height(p),
                  0.01 * (slope.x() + slope.y()),
                  2e-4);
      // Heading +x: pitch is the slope along x (nose up on a rising
      // slope: a negative pitch about y), roll the slope along y.
      const Eigen::Vector2d rp = RollPitchDeg(PoseOnGround(ground, {x, y, 0}));
      EXPECT_NEAR(rp.y(), -std::atan(slope.x()) / kDeg, 0.01);
      EXPECT_NEAR(rp.x(), std::atan(slope.y()) / kDeg, 0.01);
    }
  }
  // Secants of the slope over 5 m cells of a 60 m wave: >= 95 % of the peak.
  EXPECT_GT(max_x, 2.35);
  EXPECT_LE(max_x, 2.5);
  EXPECT_GT(max_y, 1.88);
  EXPECT_LE(max_y, 2.0);
}

// A car does not slip sideways: along the whole sloped route it moves along
// its own x axis (the motion between two nearby poses on one tile has no
// component along the car's y axis), so a wheel odometer's planar log
// measures its motion. A heading tilted into the ground's plane by the
// normal's projection would crab by up to the product of the two slopes
// (about 0.09 deg here).
TEST(RoadScene, CarOnSlopedGroundMovesAlongItsHeading) {
  RoadOptions options;
  options.slope_x_deg = 2.5;
  options.slope_y_deg = 2.0;
  const RoadGround ground = MakeRoadGround(options);
  const UnicyclePath path = MakeRoadPath(options, 12.0);
  constexpr int64_t kStepNs = 1000000;  // 1 ms: 7 mm at 7 m/s
  int checked = 0;
  double max_slip_deg = 0.0;
  for (int64_t t = kStepNs; t < 12000000000 - kStepNs; t += 50000000) {
    const PlanarPose before = path.PoseAt(t - kStepNs);
    const PlanarPose after = path.PoseAt(t + kStepNs);
    if (!ground.Gradient({before.x, before.y})
             .isApprox(ground.Gradient({after.x, after.y}))) {
      continue;  // across a tile border
    }
    const Rigid3d pose = PoseOnGround(ground, path.PoseAt(t));
    const Eigen::Vector3d motion =
        pose.rotation.conjugate() * (PoseOnGround(ground, after).translation -
                                     PoseOnGround(ground, before).translation);
    max_slip_deg = std::max(
        max_slip_deg, std::abs(std::atan2(motion.y(), motion.x())) / kDeg);
    EXPECT_GT(motion.x(), 0.0);
    ++checked;
  }
  EXPECT_GT(checked, 150);
  EXPECT_LT(max_slip_deg, 1e-4);
}

// The ground's tiles meet: every tile's corners lie on the ground.
TEST(RoadScene, GroundTilesLieOnTheGround) {
  RoadOptions options;
  options.slope_x_deg = 2.5;
  options.slope_y_deg = 2.0;
  options.last_straight_m = 5.0;
  options.margin_m = 6.0;
  options.road_texel_size_m = 0.2;  // small textures: fast
  options.ground_texel_size_m = 0.5;
  options.structure_texel_size_m = 0.5;
  options.far_texel_size_m = 1.0;
  RoomSceneOptions scene_options;
  scene_options.seed = 3;
  const RoomScene scene = BuildRoadScene(options, scene_options);
  const RoadGround ground = MakeRoadGround(options);
  ASSERT_EQ(scene.surfaces.size(), scene.textures.size());
  int tiles = 0;
  for (const Surface& s : scene.surfaces) {
    if (std::abs(s.u_axis.z()) > 0.9 || std::abs(s.v_axis.z()) > 0.9) {
      continue;  // vertical: a wall, post or facade
    }
    ++tiles;
    for (const double a : {0.0, 1.0}) {
      for (const double b : {0.0, 1.0}) {
        const Eigen::Vector3d corner = s.origin + a * s.u_extent_m * s.u_axis +
                                       b * s.v_extent_m * s.v_axis;
        EXPECT_NEAR(corner.z(), ground.Height(corner.head<2>()), 1e-9);
      }
    }
  }
  EXPECT_EQ(tiles, ground.num_cells_x() * ground.num_cells_y());
}

// The presets: 80 images at 10 Hz; the camera 1.65 m above the ground along
// the car's up axis; `road` level, `road_sloped` pitching and banking by
// 1-3 deg while its wheel odometry stays planar and integrates the distance
// along the ground (longer than the distance seen from above).
TEST(RoadScene, PresetsDriveOnTheGroundAtCarHeight) {
  for (const std::string name : {"road", "road_sloped"}) {
    SCOPED_TRACE(name);
    const RenderedDataset dataset =
        SimulateDatasetMotion(MakeDatasetPreset(name, 1));
    const RenderedDatasetOptions& o = dataset.options;
    ASSERT_TRUE(o.road.has_value());
    ASSERT_EQ(dataset.frames.size(), 80u);
    EXPECT_EQ(dataset.frames[1].capture_ns - dataset.frames[0].capture_ns,
              100000000);
    const RoadGround ground = MakeRoadGround(*o.road);
    double max_tilt = 0.0;
    for (const RenderedFrame& frame : dataset.frames) {
      const Rigid3d room_from_odom =
          frame.room_from_cam * Inverse(o.odom_from_cam);
      const Eigen::Vector3d up =
          room_from_odom.rotation * Eigen::Vector3d::UnitZ();
      const Eigen::Vector3d& car = room_from_odom.translation;
      EXPECT_NEAR(car.z(), ground.Height(car.head<2>()), 1e-9);
      EXPECT_NEAR((frame.room_from_cam.translation - car).dot(up), 1.65, 1e-9);
      max_tilt = std::max(max_tilt, std::acos(std::min(1.0, up.z())) / kDeg);
    }
    ASSERT_EQ(dataset.odometry.poses.size(),
              dataset.true_odometry_se3.poses.size());
    double planar = 0.0, along_ground = 0.0, seen_from_above = 0.0;
    const auto& se3 = dataset.true_odometry_se3.poses;
    for (size_t k = 1; k < se3.size(); ++k) {
      const Eigen::Vector3d step = se3[k].world_from_sensor.translation -
                                   se3[k - 1].world_from_sensor.translation;
      along_ground += step.norm();
      seen_from_above += step.head<2>().norm();
      planar += (dataset.odometry.poses[k].world_from_sensor.translation -
                 dataset.odometry.poses[k - 1].world_from_sensor.translation)
                    .norm();
      EXPECT_EQ(dataset.odometry.poses[k].world_from_sensor.translation.z(),
                0.0);
    }
    EXPECT_NEAR(planar / along_ground, 1.0, 1e-5);
    if (name == "road") {
      EXPECT_LT(max_tilt, 1e-6);
      EXPECT_NEAR(along_ground / seen_from_above, 1.0, 1e-9);
    } else {
      EXPECT_GT(max_tilt, 1.0);
      EXPECT_LT(max_tilt, 3.5);
      EXPECT_GT(along_ground / seen_from_above, 1.0 + 1e-4);
    }
  }
}

}  // namespace
}  // namespace odomcal
