// Planar motion of a differential-drive robot's body (a unicycle): poses
// (x, y, yaw), the exact step at a constant twist, and a path made of
// manoeuvres at constant forward speed v and yaw rate w, evaluated exactly at
// any time (the pose at time t inside a manoeuvre is the SE(2) exponential of
// (v, w) * t). The drive simulator integrates with UnicycleStep; the room
// path planner (datasets/rendering/room_path.h) produces a UnicyclePath.
//
// Planar poses are origin-free here: (x, y, yaw) in the path's frame.
#pragma once

#include "odomcal/solver/planar_pose.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace odomcal {

// The pose after dt seconds at forward speed v (m/s) and yaw rate w (rad/s),
// both constant: exact (an arc, a straight line or a turn in place).
PlanarPose UnicycleStep(const PlanarPose& pose, double v, double w, double dt);

struct PathManoeuvre {
  int64_t start_ns = 0;  // from the path start
  int64_t duration_ns = 0;
  double speed_mps = 0.0;
  double yaw_rate_radps = 0.0;
  PlanarPose start;
};

class UnicyclePath {
 public:
  UnicyclePath() = default;
  // Throws std::invalid_argument without manoeuvres.
  explicit UnicyclePath(std::vector<PathManoeuvre> manoeuvres);

  // Total duration; the path holds its last pose afterwards.
  int64_t duration_ns() const;
  const std::vector<PathManoeuvre>& manoeuvres() const { return manoeuvres_; }

  // The pose at time t (ns from the path start, clamped to the path).
  PlanarPose PoseAt(int64_t t_ns) const;

  // Integrals of the speed and yaw rate over [t0, t1]: the distance driven
  // (m) and the heading change (rad); exact for piecewise-constant twists.
  Eigen::Vector2d DistanceAndYawBetween(int64_t t0_ns, int64_t t1_ns) const;

 private:
  std::vector<PathManoeuvre> manoeuvres_;
};

}  // namespace odomcal
