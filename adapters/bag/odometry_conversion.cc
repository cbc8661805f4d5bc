#include "odomcal/adapters/bag/odometry_conversion.h"

#include "odomcal/adapters/format_error.h"
#include "odomcal/solver/rigid3.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace odomcal::bag {
namespace {

std::string Lowercase(std::string text) {
  for (char& c : text) {
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return text;
}

std::string JoinNames(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) {
    if (!text.empty()) text += ", ";
    text += "'" + name + "'";
  }
  return text.empty() ? "none" : text;
}

// Index of `name` in `names`, or -1.
int IndexOf(const std::vector<std::string>& names, const std::string& name) {
  const auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? -1 : static_cast<int>(it - names.begin());
}

}  // namespace

Rigid3d PoseFromOdometry(const OdometryMessage& odometry,
                         const std::string& context) {
  const auto& p = odometry.position;
  const auto& q = odometry.orientation;  // x, y, z, w
  for (const double value : {p[0], p[1], p[2], q[0], q[1], q[2], q[3]}) {
    if (!std::isfinite(value)) {
      throw FormatError(context +
                        ": odometry pose holds a value that is not "
                        "finite");
    }
  }
  Eigen::Quaterniond rotation(q[3], q[0], q[1], q[2]);
  const double norm = rotation.norm();
  if (std::abs(norm - 1.0) > 1e-2) {
    throw FormatError(context + ": odometry orientation (x, y, z, w) = (" +
                      std::to_string(q[0]) + ", " + std::to_string(q[1]) +
                      ", " + std::to_string(q[2]) + ", " +
                      std::to_string(q[3]) + ") is not a unit quaternion");
  }
  rotation.normalize();
  return Rigid3d(rotation, Eigen::Vector3d(p[0], p[1], p[2]));
}

Trajectory OdometryTrajectory(std::vector<StampedPose> poses,
                              const std::string& source,
                              const PlanarityTolerance& tolerance) {
  if (poses.empty()) throw FormatError(source + ": no odometry poses");
  for (size_t i = 1; i < poses.size(); ++i) {
    if (poses[i].stamp_ns <= poses[i - 1].stamp_ns) {
      throw FormatError(source + ": odometry stamp " +
                        std::to_string(poses[i].stamp_ns) +
                        " ns is not after "
                        "the previous one, " +
                        std::to_string(poses[i - 1].stamp_ns) + " ns");
    }
  }
  double min_z = poses.front().world_from_sensor.translation.z();
  double max_z = min_z;
  double max_tilt = 0.0;
  for (const StampedPose& pose : poses) {
    const double z = pose.world_from_sensor.translation.z();
    min_z = std::min(min_z, z);
    max_z = std::max(max_z, z);
    const Eigen::Vector3d up =
        pose.world_from_sensor.rotation * Eigen::Vector3d::UnitZ();
    max_tilt = std::max(max_tilt, std::acos(std::clamp(up.z(), -1.0, 1.0)));
  }
  Trajectory trajectory;
  trajectory.source = source;
  trajectory.planar = max_z - min_z <= tolerance.max_z_range_m &&
                      max_tilt <= tolerance.max_tilt_rad;
  if (trajectory.planar) {
    for (StampedPose& pose : poses) {
      Rigid3d& world_from_sensor = pose.world_from_sensor;
      const Eigen::Matrix3d rotation = world_from_sensor.rotation.matrix();
      const double yaw = std::atan2(rotation(1, 0), rotation(0, 0));
      world_from_sensor.rotation = YawRotation(yaw);
      world_from_sensor.translation.z() = 0.0;
    }
  }
  trajectory.poses = std::move(poses);
  return trajectory;
}

WheelTravelCollector::WheelTravelCollector(const WheelJointOptions& options,
                                           std::string context)
    : options_(options), context_(std::move(context)) {
  if (!(options.wheel_radius_m > 0.0) ||
      !std::isfinite(options.wheel_radius_m)) {
    throw std::invalid_argument(
        "--wheel_radius_m must be a positive number of metres (joint "
        "positions are wheel angles in rad), got " +
        std::to_string(options.wheel_radius_m));
  }
  if (options.left_joint.empty() != options.right_joint.empty()) {
    throw std::invalid_argument(
        "--left_wheel_joint and --right_wheel_joint go together: pass both "
        "or neither");
  }
  left_joint_ = options.left_joint;
  right_joint_ = options.right_joint;
  travels_.source = context_;
}

std::optional<WheelTravelSample> WheelTravelCollector::Sample(
    int64_t stamp_ns, const JointStateMessage& joints) {
  for (const std::string& name : joints.name) {
    if (std::find(names_seen_.begin(), names_seen_.end(), name) ==
        names_seen_.end()) {
      names_seen_.push_back(name);
    }
  }
  int left = -1;
  int right = -1;
  if (!options_.left_joint.empty()) {
    left = IndexOf(joints.name, options_.left_joint);
    right = IndexOf(joints.name, options_.right_joint);
  } else {
    std::vector<std::string> lefts;
    std::vector<std::string> rights;
    for (const std::string& name : joints.name) {
      const std::string lower = Lowercase(name);
      const bool is_left = lower.find("left") != std::string::npos;
      const bool is_right = lower.find("right") != std::string::npos;
      if (is_left && is_right) {
        throw FormatError(context_ + ": joint '" + name +
                          "' names both left "
                          "and right; pass --left_wheel_joint and "
                          "--right_wheel_joint");
      }
      if (is_left) lefts.push_back(name);
      if (is_right) rights.push_back(name);
    }
    if (lefts.size() > 1 || rights.size() > 1) {
      throw FormatError(context_ + ": cannot tell the wheel joints apart: " +
                        "left candidates " + JoinNames(lefts) +
                        ", right candidates " + JoinNames(rights) +
                        " (joints: " + JoinNames(joints.name) +
                        "); pass --left_wheel_joint and --right_wheel_joint");
    }
    if (lefts.size() == 1 && rights.size() == 1) {
      if (left_joint_.empty()) {
        left_joint_ = lefts[0];
        right_joint_ = rights[0];
      } else if (left_joint_ != lefts[0] || right_joint_ != rights[0]) {
        throw FormatError(context_ + ": the wheel joints change from '" +
                          left_joint_ + "'/'" + right_joint_ + "' to '" +
                          lefts[0] + "'/'" + rights[0] +
                          "'; pass --left_wheel_joint and "
                          "--right_wheel_joint");
      }
      left = IndexOf(joints.name, left_joint_);
      right = IndexOf(joints.name, right_joint_);
    }
  }
  const int positions = static_cast<int>(joints.position.size());
  if (left < 0 || right < 0 || left >= positions || right >= positions) {
    ++skipped_;
    return std::nullopt;
  }
  const double left_rad = joints.position[left];
  const double right_rad = joints.position[right];
  if (!std::isfinite(left_rad) || !std::isfinite(right_rad)) {
    throw FormatError(context_ + ": wheel joint position at " +
                      std::to_string(stamp_ns) + " ns is not finite");
  }
  WheelTravelSample sample;
  sample.stamp_ns = stamp_ns;
  sample.left_m = left_rad * options_.wheel_radius_m;
  sample.right_m = right_rad * options_.wheel_radius_m;
  return sample;
}

void WheelTravelCollector::Append(const WheelTravelSample& sample) {
  if (!travels_.samples.empty() &&
      sample.stamp_ns <= travels_.samples.back().stamp_ns) {
    throw FormatError(context_ + ": joint state stamp " +
                      std::to_string(sample.stamp_ns) +
                      " ns is not after the previous one, " +
                      std::to_string(travels_.samples.back().stamp_ns) + " ns");
  }
  travels_.samples.push_back(sample);
}

bool WheelTravelCollector::Add(int64_t stamp_ns,
                               const JointStateMessage& joints) {
  const std::optional<WheelTravelSample> sample = Sample(stamp_ns, joints);
  if (!sample) return false;
  Append(*sample);
  return true;
}

WheelTravels WheelTravelCollector::Finish() const {
  if (travels_.samples.empty()) {
    const std::string wanted =
        options_.left_joint.empty()
            ? std::string("one joint named like 'left' and one like 'right'")
            : "'" + options_.left_joint + "' and '" + options_.right_joint +
                  "'";
    throw FormatError(context_ + ": no joint state holds the wheel joints (" +
                      wanted + "); joints seen: " + JoinNames(names_seen_));
  }
  return travels_;
}

}  // namespace odomcal::bag
