#include "odomcal/datasets/rendering/room_path.h"

#include "odomcal/datasets/rendering/dataset_presets.h"
#include "odomcal/datasets/rendering/rendered_dataset.h"

#include <gtest/gtest.h>

#include <cmath>

namespace odomcal {
namespace {

// The planner checks clearances every 50 ms; between checks the robot moves
// at most 0.5 m/s * 25 ms, and the camera (<= 0.3 m from the centre at
// <= 0.7 rad/s) a little more.
constexpr double kBetweenChecksM = 0.03;

bool OnSomeFloor(const RoomLayout& layout, const Eigen::Vector2d& p) {
  for (const FloorPatch& floor : layout.floors) {
    if ((p.array() >= floor.min_xy.array()).all() &&
        (p.array() <= floor.max_xy.array()).all()) {
      return true;
    }
  }
  return false;
}

class PresetPath : public ::testing::TestWithParam<std::string> {};

TEST_P(PresetPath, StaysInsideWithClearanceAndIsContinuous) {
  for (uint64_t seed = 0; seed < 5; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const RenderedDataset dataset =
        SimulateDatasetMotion(MakeDatasetPreset(GetParam(), seed));
    const RoomPathOptions& options = dataset.options.path;
    const UnicyclePath& path = dataset.path;
    double min_robot = 1e9, min_camera = 1e9;
    for (int64_t t = 0; t <= path.duration_ns(); t += 10000000) {
      const PlanarPose pose = path.PoseAt(t);
      const Eigen::Vector2d centre(pose.x, pose.y);
      const Eigen::Vector2d camera =
          centre + Eigen::Rotation2Dd(pose.yaw_rad) *
                       options.camera_position_in_odom.head<2>();
      ASSERT_TRUE(OnSomeFloor(dataset.options.layout, centre)) << "t = " << t;
      min_robot = std::min(min_robot,
                           dataset.options.layout.DistanceToObstacles(centre));
      min_camera = std::min(min_camera,
                            dataset.options.layout.DistanceToObstacles(camera));
    }
    // Waypoint drives use 80 % of the robot clearance (narrow corridors).
    const double robot_floor = (options.legs.back().waypoints.empty() &&
                                options.legs.front().waypoints.empty())
                                   ? options.robot_clearance_m
                                   : 0.8 * options.robot_clearance_m;
    EXPECT_GE(min_robot, robot_floor - kBetweenChecksM);
    EXPECT_GE(min_camera, options.camera_clearance_m - kBetweenChecksM);
    // Manoeuvres chain exactly: each starts where the previous one ended.
    const auto& m = path.manoeuvres();
    for (size_t i = 1; i < m.size(); ++i) {
      const PlanarPose end = path.PoseAt(m[i].start_ns);
      EXPECT_NEAR(end.x, m[i].start.x, 1e-12);
      EXPECT_NEAR(end.yaw_rad, m[i].start.yaw_rad, 1e-12);
      EXPECT_EQ(m[i].start_ns, m[i - 1].start_ns + m[i - 1].duration_ns);
    }
    EXPECT_GE(path.duration_ns(),
              static_cast<int64_t>(options.duration_s * 1e9) - 1);
  }
}

INSTANTIATE_TEST_SUITE_P(RoomPath,
                         PresetPath,
                         ::testing::Values("small",
                                           "default",
                                           "tilted",
                                           "hard",
                                           "straight",
                                           "long"));

// Every seed turns both ways and mixes straight runs, stops and turns in
// place; arc radii vary across seeds.
TEST(RoomPath, MixesManoeuvresTurningBothWays) {
  double min_radius = 1e9, max_radius = 0.0;
  for (uint64_t seed = 0; seed < 5; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const RenderedDataset dataset =
        SimulateDatasetMotion(MakeDatasetPreset("small", seed));
    int left = 0, right = 0, straight = 0, stops = 0, in_place = 0;
    for (const PathManoeuvre& m : dataset.path.manoeuvres()) {
      if (m.yaw_rate_radps > 0) ++left;
      if (m.yaw_rate_radps < 0) ++right;
      if (m.yaw_rate_radps == 0 && m.speed_mps > 0) ++straight;
      if (m.yaw_rate_radps == 0 && m.speed_mps == 0) ++stops;
      if (m.yaw_rate_radps != 0 && m.speed_mps == 0) ++in_place;
      if (m.yaw_rate_radps != 0 && m.speed_mps > 0) {
        const double radius = m.speed_mps / std::abs(m.yaw_rate_radps);
        min_radius = std::min(min_radius, radius);
        max_radius = std::max(max_radius, radius);
      }
    }
    EXPECT_GE(left, 1);
    EXPECT_GE(right, 1);
    EXPECT_GE(straight, 1);
    EXPECT_GE(stops, 2);  // the initial stop and at least one more
    EXPECT_GE(in_place, 1);
  }
  EXPECT_GT(max_radius, 2.0 * min_radius);
}

TEST(RoomPath, StraightPresetNeverTurnsAndHardCrossesIntoTheSecondRoom) {
  const RenderedDataset straight =
      SimulateDatasetMotion(MakeDatasetPreset("straight", 2));
  for (const PathManoeuvre& m : straight.path.manoeuvres())
    EXPECT_EQ(m.yaw_rate_radps, 0.0);
  const RenderedDataset hard =
      SimulateDatasetMotion(MakeDatasetPreset("hard", 2));
  EXPECT_LT(hard.path.PoseAt(0).x, 5.0);                        // room A
  EXPECT_GT(hard.path.PoseAt(hard.path.duration_ns()).x, 5.2);  // room B
}

TEST(RoomPath, DeterministicForASeed) {
  const RenderedDataset a =
      SimulateDatasetMotion(MakeDatasetPreset("small", 9));
  const RenderedDataset b =
      SimulateDatasetMotion(MakeDatasetPreset("small", 9));
  const RenderedDataset c =
      SimulateDatasetMotion(MakeDatasetPreset("small", 10));
  ASSERT_EQ(a.path.manoeuvres().size(), b.path.manoeuvres().size());
  for (size_t i = 0; i < a.path.manoeuvres().size(); ++i) {
    EXPECT_EQ(a.path.manoeuvres()[i].speed_mps,
              b.path.manoeuvres()[i].speed_mps);
    EXPECT_EQ(a.path.manoeuvres()[i].duration_ns,
              b.path.manoeuvres()[i].duration_ns);
  }
  EXPECT_NE(a.path.PoseAt(5000000000).x, c.path.PoseAt(5000000000).x);
}

TEST(PlanRoomPath, RejectsAStartInsideAnObstacle) {
  RenderedDatasetOptions options = MakeDatasetPreset("small", 0);
  options.path.start = {0.1, 0.1, 0.0};  // in the corner
  EXPECT_THROW(SimulateDatasetMotion(options), std::invalid_argument);
}

// The `long` preset drives 5 minutes: into room B through the corridor and
// back into room A, turning both ways, and never stands still for long
// (before more_turns_when_stuck it stood still for 26 of 36 s, seed 1).
TEST(LongPreset, DrivesThroughBothRoomsAndBackWithoutLongStops) {
  for (const uint64_t seed : {1u, 2u}) {
    const RenderedDataset motion =
        SimulateDatasetMotion(MakeDatasetPreset("long", seed));
    const UnicyclePath& path = motion.path;
    EXPECT_GE(1e-9 * path.duration_ns(), 300.0);
    double max_x = 0.0, left = 0.0, right = 0.0, stop_s = 0.0,
           longest_stop_s = 0.0;
    for (const PathManoeuvre& m : path.manoeuvres()) {
      max_x = std::max(max_x, m.start.x);
      const double seconds = 1e-9 * m.duration_ns;
      if (m.yaw_rate_radps > 0.0) left += seconds;
      if (m.yaw_rate_radps < 0.0) right += seconds;
      if (m.speed_mps == 0.0 && m.yaw_rate_radps == 0.0) {
        stop_s += seconds;
        longest_stop_s = std::max(longest_stop_s, stop_s);
      } else {
        stop_s = 0.0;
      }
    }
    // Room B starts at x = 5.2 m in the room frame; the path ends in A.
    EXPECT_GT(max_x, 6.5) << "seed " << seed;
    EXPECT_LT(path.PoseAt(path.duration_ns()).x, 5.0) << "seed " << seed;
    EXPECT_GT(left, 20.0) << "seed " << seed;
    EXPECT_GT(right, 20.0) << "seed " << seed;
    EXPECT_LE(longest_stop_s, 3.0) << "seed " << seed;
  }
}

}  // namespace
}  // namespace odomcal
