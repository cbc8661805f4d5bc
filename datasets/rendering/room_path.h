// A differential-drive robot's path through a RoomLayout, planned at random
// but reproducibly from a seed: a UnicyclePath (datasets/simulation/
// unicycle_path.h), a sequence of manoeuvres at constant forward speed v and
// yaw rate w, evaluated exactly at any time. Each leg first *wanders* inside a
// region for a duration, cycling through straight runs, arcs of random radius
// turning left and right in alternation, turns in place and stops, at random
// speeds; then drives through the leg's waypoints at the maximum rates (turn in
// place to face the next one, drive straight to it). A candidate manoeuvre is
// accepted only when, sampled every 50 ms, (1) the robot centre stays inside
// the region (waypoint drives: anywhere) at least robot_clearance_m from every
// wall and box, (2) the camera centre stays camera_clearance_m away from them,
// and (3) the view along the camera's horizontal viewing direction reaches at
// least min_view_depth_m (no close-ups of a wall). After repeated rejections
// the robot turns in place towards the region's centre. Waypoint drives that
// violate the clearances make the planner retry the whole leg with fresh
// random numbers, and finally throw std::runtime_error.
//
// Planar poses are in the room frame.
#pragma once

#include "odomcal/datasets/rendering/room_layout.h"
#include "odomcal/datasets/simulation/unicycle_path.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace odomcal {

struct PathLeg {
  // Wander region for the robot centre (axis-aligned, room frame).
  Eigen::Vector2d region_min = Eigen::Vector2d::Zero();
  Eigen::Vector2d region_max = Eigen::Vector2d::Ones();
  double wander_duration_s = 10.0;  // the last leg also fills up to duration
  std::vector<Eigen::Vector2d> waypoints;  // driven through after wandering
};

struct RoomPathOptions {
  uint64_t seed = 0;
  PlanarPose start;  // must satisfy the clearances
  std::vector<PathLeg> legs;
  double duration_s = 10.0;     // the path is at least this long
  double initial_stop_s = 0.5;  // standing still first
  double min_speed_mps = 0.2, max_speed_mps = 0.5;
  double min_yaw_rate_radps = 0.25, max_yaw_rate_radps = 0.7;
  double min_manoeuvre_s = 1.0, max_manoeuvre_s = 2.5;
  bool straight_only = false;  // only straight runs and stops (no turns)
  double robot_clearance_m = 0.6;
  double camera_clearance_m = 0.3;
  double min_view_depth_m = 0.9;
  // Where the camera sits and looks, in the odometry frame (from the mount):
  // its (x, y) position and its optical axis.
  Eigen::Vector3d camera_position_in_odom = Eigen::Vector3d::Zero();
  Eigen::Vector3d camera_axis_in_odom = Eigen::Vector3d::UnitX();
  // When no manoeuvre and no turn towards the region's centre is valid, try
  // quarter and half turns before standing still (off in the older presets,
  // whose paths stay as they were).
  bool more_turns_when_stuck = false;
  void Check() const;  // throws std::invalid_argument naming the field
};

// Plans a path (see above). Throws std::invalid_argument for bad options or
// an invalid start, std::runtime_error when no valid path is found.
UnicyclePath PlanRoomPath(const RoomLayout& layout,
                          const RoomPathOptions& options);

}  // namespace odomcal
