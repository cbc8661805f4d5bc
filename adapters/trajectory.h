// A timestamped sequence of poses of one sensor in a fixed frame.
//
// Used for both inputs: wheel odometry (world = `origin`, sensor = `odom`,
// metres) and camera trajectories (world = the reconstruction's frame,
// sensor = `cam`, reconstruction units). Pose i maps sensor coordinates at
// time poses[i].stamp_ns into the world frame:
//   x_in_world = poses[i].world_from_sensor * x_in_sensor.
// The readers in trajectory_io.h guarantee strictly increasing stamps and unit
// quaternions; code that builds a Trajectory by hand must do the same.
#pragma once

#include "odomcal/adapters/timestamp.h"
#include "odomcal/solver/rigid3.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace odomcal {

struct StampedPose {
  int64_t stamp_ns = 0;
  Rigid3d world_from_sensor;
};

struct Trajectory {
  // Strictly increasing stamp_ns.
  std::vector<StampedPose> poses;
  // True for x, y, yaw logs (z = 0, rotation about +z only). Interpolation
  // then follows the SE(2) geodesic, which is exact for a unicycle at
  // constant linear and angular velocity.
  bool planar = false;
  // Where the poses came from (usually the file path), for messages.
  std::string source;
  // The unit its file's timestamps were read in, when a reader knows it
  // (e.g. a CSV header's time_ms overrides the unit flag's default).
  std::optional<TimeUnit> time_unit;
};

}  // namespace odomcal
