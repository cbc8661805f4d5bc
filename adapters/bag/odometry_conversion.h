// nav_msgs/Odometry and sensor_msgs/JointState -> odomcal's odometry inputs.
//
// Conventions at this boundary: stamps are integer nanoseconds (which stamp,
// header or receive time, is the caller's choice); ROS quaternions come as
// (x, y, z, w) and become Eigen's Quaterniond(w, x, y, z); the pose of a
// nav_msgs/Odometry is origin_from_odom (header.frame_id from
// child_frame_id), odomcal's world_from_sensor of the odometry trajectory.
//
// Joint positions of wheels are ANGLES in radians; a wheel's travel is
// angle * wheel_radius_m (cumulative, like the angle).
//
// Problems in the data throw FormatError("<context>: <problem>"), context
// naming the bag and topic; bad arguments std::invalid_argument.
#pragma once

#include "odomcal/adapters/bag/ros_messages.h"
#include "odomcal/adapters/trajectory.h"
#include "odomcal/adapters/wheel_travel.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace odomcal::bag {

// origin_from_odom of one message; the quaternion is normalised (its norm
// must be within 1e-2 of 1, else FormatError).
Rigid3d PoseFromOdometry(const OdometryMessage& odometry,
                         const std::string& context);

// When a log counts as planar: over the whole log, z stays within
// max_z_range_m (max - min) and every pose's z axis within max_tilt_rad of
// the vertical (roll and pitch).
struct PlanarityTolerance {
  double max_z_range_m = 1e-3;
  double max_tilt_rad = 1e-3;
};

// The trajectory of `poses` (stamps strictly increasing, else FormatError
// naming both stamps). When the log is planar (see above) every pose is
// flattened to (x, y, 0) and its yaw about +z, and planar = true, so
// WriteOdometryCsv writes it; otherwise the poses are kept (SE(3), TUM).
// Throws FormatError when `poses` is empty.
Trajectory OdometryTrajectory(std::vector<StampedPose> poses,
                              const std::string& source,
                              const PlanarityTolerance& tolerance = {});

// Which joints are the wheels. Empty names: found by "left" and "right" in
// the joint names (case-insensitive; exactly one joint each).
struct WheelJointOptions {
  std::string left_joint;
  std::string right_joint;
  double wheel_radius_m = 0.0;  // > 0
};

// Collects wheel travels from JointState messages in stream order. A message
// without both wheel joints (or without their positions) is skipped; joints
// may come in any order in each message.
class WheelTravelCollector {
 public:
  // Throws std::invalid_argument for a wheel radius that is not > 0 and
  // finite, or one joint name given without the other.
  WheelTravelCollector(const WheelJointOptions& options, std::string context);

  // The sample of `joints` at stamp_ns, or std::nullopt (counted as
  // skipped) when the message lacks a wheel joint or its position. Throws
  // FormatError when the names are ambiguous (several joints match "left"
  // or "right", or another pair than before) or a position is not finite.
  std::optional<WheelTravelSample> Sample(int64_t stamp_ns,
                                          const JointStateMessage& joints);
  // Appends a sample; FormatError when its stamp is not after the last one.
  void Append(const WheelTravelSample& sample);
  // Sample() and, unless skipped, Append(); false when skipped.
  bool Add(int64_t stamp_ns, const JointStateMessage& joints);

  // The joints found (empty before the first sample).
  const std::string& left_joint() const { return left_joint_; }
  const std::string& right_joint() const { return right_joint_; }
  // Messages skipped for lacking the joints.
  int64_t skipped() const { return skipped_; }

  // The travels; FormatError when no message held both joints (the message
  // lists the joint names seen).
  WheelTravels Finish() const;

 private:
  WheelJointOptions options_;
  std::string context_;
  std::string left_joint_;
  std::string right_joint_;
  std::vector<std::string> names_seen_;
  int64_t skipped_ = 0;
  WheelTravels travels_;
};

}  // namespace odomcal::bag
