// Preset numbers: the focal lengths give a 63 deg horizontal field of view.
// Speeds of 0.3-0.6 m/s and 0.25-0.6 rad/s at 2.5 Hz put consecutive images
// 12-24 cm and <= 14 deg apart: overlapping enough for sequential matching,
// with baselines wide enough for COLMAP's initialisation (measured: at 4 Hz
// and 0.2-0.5 m/s, 3-12 cm steps, the mapper built wrong models, 4-35 deg,
// in 4 of 5 runs of small/tilted variants although every two-view geometry
// agreed with the ground truth).

#include "odomcal/datasets/rendering/dataset_presets.h"

#include "odomcal/datasets/simulation/camera_mount.h"

#include <stdexcept>
#include <vector>

namespace odomcal {
namespace {

RoomLayout StandardRoom() {
  using V = Eigen::Vector2d;
  using S = Eigen::Vector3d;
  return MakeRectangularRoom(8.0,
                             6.0,
                             2.5,
                             /*ceiling=*/true,
                             {{V(1.3, 1.1), 0.35, S(0.8, 0.6, 0.7), true},
                              {V(6.7, 4.8), -0.25, S(0.6, 0.6, 1.0), true},
                              {V(6.6, 1.1), 0.0, S(0.4, 0.4, 2.5), true},
                              {V(2.2, 5.1), 0.1, S(1.0, 0.5, 0.5), true},
                              {V(4.6, 3.6), 0.0, S(0.35, 0.35, 2.5), true}});
}

PathLeg WholeRoom(const RoomLayout& layout) {
  PathLeg leg;
  leg.region_min = layout.floors[0].min_xy;
  leg.region_max = layout.floors[0].max_xy;
  leg.wander_duration_s = 0.0;  // single leg: wanders for the whole path
  return leg;
}

// Mild, realistic wheel odometry errors.
WheelOdometryNoise MildNoise() {
  WheelOdometryNoise noise;
  noise.wheel_scale_error_left = 0.003;
  noise.wheel_scale_error_right = -0.002;
  noise.wheel_slip_stddev = 0.001;
  noise.yaw_rate_bias_radps = 0.002;
  return noise;
}

RenderedDatasetOptions Small() {
  RenderedDatasetOptions o;
  o.camera = {320, 240, 260.0, 260.0, 160.0, 120.0, 0.0};
  o.odom_from_cam =
      MakeCameraMount(0.0, 0.0, 0.0, Eigen::Vector3d(0.25, 0.05, 0.40));
  o.layout = StandardRoom();
  o.path.legs = {WholeRoom(o.layout)};
  o.path.start = {2.2, 2.6, 0.0};
  o.num_images = 40;
  o.camera_rate_hz = 2.5;
  o.path.min_speed_mps = 0.3;
  o.path.max_speed_mps = 0.6;
  o.path.max_yaw_rate_radps = 0.6;
  // Exact odometry: `small` and `tilted` measure what COLMAP and the
  // calibration add (the e2e tolerances of 0.1 deg / 5 mm / 0.3 %). Mild noise
  // alone (a 0.002 rad/s yaw bias turns the heading 1.8 deg in 16 s) puts the
  // yaw error near 0.1 deg; `default` and `hard` carry noise.
  return o;
}

// A car's forward camera on a road (road_scene.h): 640x200 (KITTI's 1226x370
// field of view, 82 x 30 deg, at half the size), 1.65 m above the ground,
// 1.5 m ahead of the odometry's origin (the rear axle), turned 1.5 deg left,
// pitched 2 deg down, rolled 0.5 deg; 80 images at 10 Hz.
RenderedDatasetOptions Road() {
  RenderedDatasetOptions o;
  o.camera = {640, 200, 370.0, 370.0, 320.0, 100.0, 0.0};
  o.odom_from_cam =
      MakeCameraMount(1.5, 2.0, 0.5, Eigen::Vector3d(1.5, 0.1, 1.65));
  o.layout = StandardRoom();  // unused: the road replaces it
  o.road = RoadOptions();
  o.num_images = 80;
  o.camera_rate_hz = 10.0;
  o.odometry_rate_hz = 50.0;
  o.odometry_noise.wheel_base_m = 1.6;
  o.render.background_rgb = Eigen::Vector3f(0.72f, 0.78f, 0.86f);  // sky
  return o;
}

}  // namespace

std::vector<DatasetPresetInfo> DatasetPresets() {
  return {
      {"small",
       "CI: 40 images 320x240 at 2.5 Hz, forward camera, 8 x 6 m room"},
      {"default", "the demo: 64 images 320x240 at 2.5 Hz, forward camera"},
      {"tilted",
       "40 images 320x240, camera pitched 10 deg down, rolled 90 deg"},
      {"hard",
       "two rooms + featureless corridor (model splits), noisy odometry, "
       "time offset and jitter; 130 images 320x240 at 2.5 Hz"},
      {"straight", "straight driving only (rotation unobservable), 40 images"},
      {"long",
       "long drive: room, textured corridor, second room and back (a loop), "
       "1000 images 320x240 at 3.3 Hz (5 min)"},
      {"road",
       "a car on a road (straight, left turn, straight, right turn): "
       "forward camera 1.65 m up, 80 images 640x200 at 10 Hz, sparse road "
       "texture"},
      {"road_sloped",
       "road on ground that pitches and banks up to 2.5 deg: SE(3) poses, "
       "planar wheel odometry (and the SE(3) one in odometry_se3.tum)"},
  };
}

RenderedDatasetOptions MakeDatasetPreset(const std::string& name,
                                         uint64_t seed) {
  RenderedDatasetOptions o = Small();
  if (name == "small") {
  } else if (name == "default") {
    // 480x360 gives ~4300 SIFT features per image: sequential matching of
    // 64 such images took 7.8 min on the 2 loaded cores; the demo must
    // reconstruct in about 2 min, so it keeps small's resolution.
    o.num_images = 64;
    o.odometry_noise = MildNoise();
  } else if (name == "tilted") {
    // Pitched 20 deg down from 0.7 m, half of every image was floor (a
    // dominant plane): COLMAP folded, drifted or failed for each of seeds 1-4
    // (0.2-1 deg, 6-26 % scale, or refused). 10 deg from 0.5 m keeps the
    // walls in view.
    o.odom_from_cam =
        MakeCameraMount(0.0, 10.0, 90.0, Eigen::Vector3d(0.10, -0.15, 0.50));
    // Rolled 90 deg, the horizontal field of view is 49 deg, not 63: turn
    // slower so that consecutive images overlap as much as small's.
    o.path.max_yaw_rate_radps = 0.45;
  } else if (name == "hard") {
    o.layout = MakeTwoRoomsWithCorridor(2.5, /*ceiling=*/true);
    PathLeg room_a;
    room_a.region_min = Eigen::Vector2d(0.0, 0.0);
    room_a.region_max = Eigen::Vector2d(5.0, 4.5);
    room_a.wander_duration_s = 14.0;
    room_a.waypoints = TwoRoomsCorridorWaypoints();
    PathLeg room_b;
    room_b.region_min = Eigen::Vector2d(5.2, 0.0);
    room_b.region_max = Eigen::Vector2d(10.2, 4.5);
    room_b.wander_duration_s = 0.0;
    o.path.legs = {room_a, room_b};
    o.path.start = {2.0, 2.2, 0.0};
    // The corridor is 1.2 m wide: its centre line is 0.6 m from the walls.
    o.path.robot_clearance_m = 0.5;
    o.path.camera_clearance_m = 0.24;
    o.num_images = 130;
    o.camera_rate_hz = 2.5;
    o.camera_time_offset_s = 0.025;
    o.camera_time_jitter_s = 0.002;
    o.odometry_noise.wheel_scale_error_left = 0.015;
    o.odometry_noise.wheel_scale_error_right = -0.010;
    o.odometry_noise.wheel_slip_stddev = 0.01;
    o.odometry_noise.yaw_rate_bias_radps = 0.01;
  } else if (name == "straight") {
    // Looking 15 deg to the left: pure forward motion is weak for SfM.
    o.odom_from_cam =
        MakeCameraMount(15.0, 0.0, 0.0, Eigen::Vector3d(0.25, 0.05, 0.40));
    o.path.straight_only = true;
    o.path.start = {0.9, 2.5, 0.0};
  } else if (name == "long") {
    // A long drive (issue 18): room A, the corridor (textured here), room B,
    // back through the corridor into room A (a loop), turning both ways;
    // 1000 images at 3.3 Hz are 5 minutes. Mild wheel noise.
    o.layout = MakeTwoRoomsWithCorridor(2.5,
                                        /*ceiling=*/true,
                                        /*textured_corridor=*/true);
    const std::vector<Eigen::Vector2d> there = TwoRoomsCorridorWaypoints();
    const std::vector<Eigen::Vector2d> back(there.rbegin(), there.rend());
    PathLeg room_a;
    room_a.region_min = Eigen::Vector2d(0.0, 0.0);
    room_a.region_max = Eigen::Vector2d(5.0, 4.5);
    room_a.wander_duration_s = 60.0;
    room_a.waypoints = there;
    PathLeg room_b;
    room_b.region_min = Eigen::Vector2d(5.2, 0.0);
    room_b.region_max = Eigen::Vector2d(10.2, 4.5);
    room_b.wander_duration_s = 120.0;
    room_b.waypoints = back;
    PathLeg room_a_again = room_a;
    room_a_again.wander_duration_s = 0.0;  // the rest of the drive
    room_a_again.waypoints.clear();
    o.path.legs = {room_a, room_b, room_a_again};
    o.path.start = {2.0, 2.2, 0.0};
    o.path.robot_clearance_m = 0.5;
    o.path.camera_clearance_m = 0.24;
    o.path.more_turns_when_stuck = true;
    o.num_images = 1000;
    o.camera_rate_hz = 10.0 / 3.0;
    o.odometry_noise = MildNoise();
  } else if (name == "road") {
    o = Road();
  } else if (name == "road_sloped") {
    o = Road();
    o.road->slope_x_deg = 2.5;
    o.road->slope_y_deg = 2.0;
  } else {
    std::string names;
    for (const DatasetPresetInfo& info : DatasetPresets()) {
      names += (names.empty() ? "" : ", ") + info.name;
    }
    throw std::invalid_argument("unknown preset '" + name +
                                "' (valid: " + names + ")");
  }
  o.preset = name;
  o.seed = seed;
  return o;
}

}  // namespace odomcal
