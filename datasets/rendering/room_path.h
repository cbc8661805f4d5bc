// A differential-drive robot's path through a RoomLayout, planned at random
// but reproducibly from a seed, and evaluated exactly at any time.
//
// The path is a sequence of manoeuvres at constant forward speed v and yaw
// rate w (a unicycle; the pose at time t inside a manoeuvre is the SE(2)
// exponential of (v, w) * t). Each leg first *wanders* inside a region for a
// duration, cycling through straight runs, arcs of random radius turning left
// and right in alternation, turns in place and stops, at random speeds; then
// drives through the leg's waypoints at the maximum rates (turn in place to
// face the next one, drive straight to it). A candidate manoeuvre is accepted
// only when, sampled every 50 ms, (1) the robot centre stays inside the region
// (waypoint drives: anywhere) at least robot_clearance_m from every wall and
// box, (2) the camera centre stays camera_clearance_m away from them, and (3)
// the view along the camera's horizontal viewing direction reaches at least
// min_view_depth_m (no close-ups of a wall). After repeated rejections the
// robot turns in place towards the region's centre. Waypoint drives that
// violate the clearances make the planner retry the whole leg with fresh
// random numbers, and finally throw std::runtime_error.
//
// Planar poses are origin-free here: (x, y, yaw) in the room frame.
#pragma once

#include "odomcal/datasets/rendering/room_layout.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace odomcal {

struct PlanarPose {
  double x = 0.0, y = 0.0, yaw_rad = 0.0;
  Rigid3d ToRigid3d() const;  // rotation about +z, z = 0
};

struct PathManoeuvre {
  int64_t start_ns = 0;  // from the path start
  int64_t duration_ns = 0;
  double speed_mps = 0.0;
  double yaw_rate_radps = 0.0;
  PlanarPose start;
};

class RoomPath {
 public:
  RoomPath() = default;
  explicit RoomPath(std::vector<PathManoeuvre> manoeuvres);

  // Total duration; the path holds its last pose afterwards.
  int64_t duration_ns() const;
  const std::vector<PathManoeuvre>& manoeuvres() const { return manoeuvres_; }

  // room_from_odom at time t (ns from the path start, clamped to the path).
  PlanarPose PoseAt(int64_t t_ns) const;

  // Integrals of the speed and yaw rate over [t0, t1]: the distance driven
  // (m) and the heading change (rad); exact for piecewise-constant twists.
  Eigen::Vector2d DistanceAndYawBetween(int64_t t0_ns, int64_t t1_ns) const;

 private:
  std::vector<PathManoeuvre> manoeuvres_;
};

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
  void Check() const;  // throws std::invalid_argument naming the field
};

// Plans a path (see above). Throws std::invalid_argument for bad options or
// an invalid start, std::runtime_error when no valid path is found.
RoomPath PlanRoomPath(const RoomLayout& layout, const RoomPathOptions& options);

}  // namespace odomcal
