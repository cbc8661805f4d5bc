#include "odomcal/adapters/robot_description.h"

#include "odomcal/solver/angles.h"
#include "odomcal/solver/format_number.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace odomcal {
namespace {

constexpr size_t kMaxFrameNameLength = 200;

void CheckFrameName(const std::string& name, const char* flag) {
  if (name.empty() || name.size() > kMaxFrameNameLength) {
    throw std::invalid_argument(std::string(flag) +
                                " must be 1 to 200 characters, got \"" + name +
                                "\"");
  }
  for (const char c : name) {
    const bool allowed = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                         (c >= '0' && c <= '9') || c == '_' || c == '-' ||
                         c == '.' || c == '/';
    if (!allowed) {
      throw std::invalid_argument(
          std::string(flag) + " \"" + name +
          "\" is not a frame name: use letters, digits and _ - . /");
    }
  }
}

// The numbers of a transform as ROS writes them.
struct TransformNumbers {
  Eigen::Vector3d xyz;
  Eigen::Vector3d rpy;
  Eigen::Quaterniond q;  // w >= 0
};

TransformNumbers NumbersOf(const Rigid3d& parent_from_child) {
  const Eigen::Quaterniond q =
      WithPositiveScalar(parent_from_child.rotation.normalized());
  return {parent_from_child.translation, RollPitchYaw(q), q};
}

std::string Triple(const Eigen::Vector3d& v) {
  return RobotNumber(v.x()) + " " + RobotNumber(v.y()) + " " +
         RobotNumber(v.z());
}

std::string HeldHeightNote(const RobotDescription& robot) {
  return "the camera height (z = " + FormatNumber(robot.held_height_m) +
         " m above " + robot.frames.base_frame +
         ") is the value given with --fixed_translation_z_m, not measured: "
         "planar driving does not determine it";
}

}  // namespace

void RobotFrameNames::Check() const {
  CheckFrameName(base_frame, "--base_frame");
  CheckFrameName(camera_frame, "--camera_frame");
  if (!camera_body_frame.empty()) {
    CheckFrameName(camera_body_frame, "--camera_body_frame");
  }
  if (base_frame == camera_frame || base_frame == camera_body_frame ||
      camera_frame == camera_body_frame) {
    throw std::invalid_argument(
        "--base_frame, --camera_frame and --camera_body_frame must name "
        "different frames, got \"" +
        base_frame + "\", \"" + camera_frame + "\" and \"" + camera_body_frame +
        "\"");
  }
}

std::optional<DiffDriveCorrections> DiffDriveCorrectionsFrom(
    const OdometryIntrinsics& intrinsics,
    const std::array<bool, 3>& estimated,
    const std::array<double, 3>& stddev) {
  const double b = intrinsics.wheel_track_m;
  const double yaw_scale = intrinsics.yaw_scale;
  if (!estimated[0] || !(b > 0.0) || !(yaw_scale > 0.0) ||
      !std::isfinite(intrinsics.yaw_per_metre_rad)) {
    return std::nullopt;
  }
  // yaw_scale = ((kl + kr) / 2) / k_track and yaw_per_metre = (kr - kl) /
  // (k_track b) (odometry_intrinsics.h); with (kl + kr) / 2 = 1:
  // k_track = 1 / yaw_scale, kr - kl = yaw_per_metre b / yaw_scale.
  DiffDriveCorrections corrections;
  corrections.wheel_separation_multiplier = 1.0 / yaw_scale;
  const double difference = intrinsics.yaw_per_metre_rad * b / yaw_scale;
  corrections.left_wheel_radius_multiplier = 1.0 - 0.5 * difference;
  corrections.right_wheel_radius_multiplier = 1.0 + 0.5 * difference;
  corrections.wheel_separation_multiplier_stddev =
      stddev[0] / (yaw_scale * yaw_scale);
  corrections.radius_difference_estimated = estimated[1];
  if (estimated[1]) {
    const double d_yaw_per_metre = 0.5 * b / yaw_scale;
    const double d_yaw_scale = 0.5 * difference / yaw_scale;
    corrections.wheel_radius_multiplier_stddev =
        std::hypot(d_yaw_per_metre * stddev[1], d_yaw_scale * stddev[0]);
  }
  if (estimated[2]) {
    corrections.yaw_rate_bias_rad_s = intrinsics.yaw_rate_bias_rad_s;
  }
  return corrections;
}

Rigid3d BodyFromOpticalRotation() {
  // Rz(-pi/2) Rx(-pi/2): optical z (forward) -> body x, optical x (right)
  // -> body -y, optical y (down) -> body -z.
  const Eigen::Quaterniond q =
      Eigen::AngleAxisd(-0.5 * kPi, Eigen::Vector3d::UnitZ()) *
      Eigen::AngleAxisd(-0.5 * kPi, Eigen::Vector3d::UnitX());
  return Rigid3d(q, Eigen::Vector3d::Zero());
}

RobotDescription MakeRobotDescription(
    const Rigid3d& base_from_optical,
    const RobotFrameNames& frames,
    bool height_held,
    std::optional<DiffDriveCorrections> diff_drive) {
  RobotDescription robot;
  robot.frames = frames;
  robot.height_held = height_held;
  robot.held_height_m = base_from_optical.translation.z();
  robot.diff_drive = diff_drive;
  if (frames.camera_body_frame.empty()) {
    robot.transforms.push_back(
        {frames.base_frame, frames.camera_frame, base_from_optical});
  } else {
    const Rigid3d body_from_optical = BodyFromOpticalRotation();
    robot.transforms.push_back(
        {frames.base_frame,
         frames.camera_body_frame,
         base_from_optical * Inverse(body_from_optical)});
    robot.transforms.push_back(
        {frames.camera_body_frame, frames.camera_frame, body_from_optical});
  }
  return robot;
}

std::string RobotNumber(double value) {
  if (std::abs(value) < 1e-12) return "0";
  return FormatRounded(value, 12);
}

std::string UrdfFragment(const RobotDescription& robot) {
  std::ostringstream out;
  out << "<!-- " << kRobotOutputMarker << ": the camera on "
      << robot.frames.base_frame << ". Paste into the robot's URDF; "
      << robot.frames.base_frame
      << " must exist there, drop a <link> below if the robot already has "
         "it. -->\n";
  if (robot.height_held) out << "<!-- " << HeldHeightNote(robot) << " -->\n";
  for (const FrameTransform& transform : robot.transforms) {
    out << "<link name=\"" << transform.child << "\"/>\n";
  }
  for (const FrameTransform& transform : robot.transforms) {
    const TransformNumbers numbers = NumbersOf(transform.parent_from_child);
    out << "<joint name=\"" << transform.parent << "_to_" << transform.child
        << "\" type=\"fixed\">\n"
        << "  <parent link=\"" << transform.parent << "\"/>\n"
        << "  <child link=\"" << transform.child << "\"/>\n"
        << "  <origin xyz=\"" << Triple(numbers.xyz) << "\" rpy=\""
        << Triple(numbers.rpy) << "\"/>\n"
        << "</joint>\n";
  }
  return out.str();
}

std::string Ros2StaticTransformCommands(const RobotDescription& robot) {
  std::ostringstream out;
  out << "# " << kRobotOutputMarker << ": tf2_ros (ROS 2) static transforms\n";
  if (robot.height_held) out << "# " << HeldHeightNote(robot) << "\n";
  for (const FrameTransform& transform : robot.transforms) {
    const TransformNumbers n = NumbersOf(transform.parent_from_child);
    out << "ros2 run tf2_ros static_transform_publisher"
        << " --x " << RobotNumber(n.xyz.x()) << " --y "
        << RobotNumber(n.xyz.y()) << " --z " << RobotNumber(n.xyz.z())
        << " --qx " << RobotNumber(n.q.x()) << " --qy " << RobotNumber(n.q.y())
        << " --qz " << RobotNumber(n.q.z()) << " --qw " << RobotNumber(n.q.w())
        << " --frame-id " << transform.parent << " --child-frame-id "
        << transform.child << "\n";
  }
  return out.str();
}

std::string Ros1StaticTransformCommands(const RobotDescription& robot) {
  std::ostringstream out;
  out << "# " << kRobotOutputMarker << ": tf (ROS 1) static transforms\n";
  if (robot.height_held) out << "# " << HeldHeightNote(robot) << "\n";
  for (const FrameTransform& transform : robot.transforms) {
    const TransformNumbers n = NumbersOf(transform.parent_from_child);
    out << "rosrun tf static_transform_publisher " << Triple(n.xyz) << " "
        << RobotNumber(n.q.x()) << " " << RobotNumber(n.q.y()) << " "
        << RobotNumber(n.q.z()) << " " << RobotNumber(n.q.w()) << " "
        << transform.parent << " " << transform.child << " 100\n";
  }
  return out.str();
}

std::string AutowareSensorsCalibrationYaml(const RobotDescription& robot) {
  std::ostringstream out;
  out << "# " << kRobotOutputMarker
      << ": Autoware sensors_calibration.yaml entry\n";
  if (robot.height_held) out << "# " << HeldHeightNote(robot) << "\n";
  std::string parent;
  for (const FrameTransform& transform : robot.transforms) {
    const TransformNumbers n = NumbersOf(transform.parent_from_child);
    if (transform.parent != parent) {
      out << transform.parent << ":\n";
      parent = transform.parent;
    }
    out << "  " << transform.child << ":\n"
        << "    x: " << RobotNumber(n.xyz.x()) << "\n"
        << "    y: " << RobotNumber(n.xyz.y()) << "\n"
        << "    z: " << RobotNumber(n.xyz.z()) << "\n"
        << "    roll: " << RobotNumber(n.rpy.x()) << "\n"
        << "    pitch: " << RobotNumber(n.rpy.y()) << "\n"
        << "    yaw: " << RobotNumber(n.rpy.z()) << "\n";
  }
  return out.str();
}

std::string DiffDriveControllerYaml(const RobotDescription& robot) {
  if (!robot.diff_drive) return "";
  const DiffDriveCorrections& c = *robot.diff_drive;
  std::ostringstream out;
  out << "# " << kRobotOutputMarker
      << ": ros2_control diff_drive_controller parameters\n"
      << "# Multipliers of the configured wheel_separation and wheel radii.\n"
      << "# Their common distance scale is held at 1: a monocular camera "
         "measures\n"
      << "# distances in the odometry's own metres.\n";
  if (!c.radius_difference_estimated) {
    out << "# The wheel radius difference was not estimated: the radius "
           "multipliers are 1.\n";
  }
  if (c.yaw_rate_bias_rad_s != 0.0) {
    out << "# A heading drift of " << FormatRounded(c.yaw_rate_bias_rad_s)
        << " rad/s was estimated too; it has no diff_drive_controller "
           "parameter.\n";
  }
  out << "diff_drive_controller:\n"
      << "  ros__parameters:\n"
      << "    wheel_separation_multiplier: "
      << RobotNumber(c.wheel_separation_multiplier) << "\n"
      << "    left_wheel_radius_multiplier: "
      << RobotNumber(c.left_wheel_radius_multiplier) << "\n"
      << "    right_wheel_radius_multiplier: "
      << RobotNumber(c.right_wheel_radius_multiplier) << "\n";
  return out.str();
}

}  // namespace odomcal
