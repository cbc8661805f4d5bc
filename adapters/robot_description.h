// The extrinsic and the odometry corrections in the forms robots load: a URDF
// fragment, tf static transform publisher commands (ROS 2 and ROS 1), an
// Autoware sensors_calibration.yaml entry and the parameters of ros2_control's
// diff_drive_controller. All of them are written from one RobotDescription.
//
// Conventions, as ROS defines them:
// - parent_from_child maps child coordinates to parent coordinates
//   (x_parent = parent_from_child * x_child); a URDF joint's <origin> and a
//   tf transform from frame_id to child_frame_id are this transform.
// - odomcal's odometry frame is the robot's base frame (x forward, y left,
//   z up) and its camera frame is the optical frame of OpenCV and COLMAP
//   (x right, y down, z forward), REP 103's "_optical_frame".
// - The camera body frame of REP 103 (x forward, y left, z up) is the
//   optical frame turned by roll -pi/2, yaw -pi/2: body_from_optical has
//   URDF rpy (-pi/2, 0, -pi/2).
// - rpy are URDF's fixed-axis angles in radians: R = Rz(yaw) Ry(pitch)
//   Rx(roll), RollPitchYaw of rigid3.h. Quaternions are written x, y, z, w (ROS
//   order), w >= 0.
#pragma once

#include "odomcal/adapters/robot_output_marker.h"
#include "odomcal/solver/odometry_intrinsics.h"
#include "odomcal/solver/rigid3.h"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace odomcal {

struct RobotFrameNames {
  std::string base_frame = "base_link";               // --base_frame
  std::string camera_frame = "camera_optical_frame";  // --camera_frame
  // REP 103 body frame of the camera (e.g. camera_link); empty: none.
  std::string camera_body_frame;  // --camera_body_frame
  // Throws std::invalid_argument naming the flag: a name must be 1-200
  // characters of A-Z a-z 0-9 _ - . / (tf frame ids, XML-safe) and the
  // names must differ.
  void Check() const;
};

struct FrameTransform {
  std::string parent;
  std::string child;
  Rigid3d parent_from_child;
};

// Wheel corrections for ros2_control's diff_drive_controller: the true
// track over the configured one and each wheel's true radius over the
// configured one. The mean radius factor (kl + kr) / 2 is held at 1: a
// monocular camera measures distances in the odometry's own metres.
struct DiffDriveCorrections {
  double wheel_separation_multiplier = 1.0;
  double left_wheel_radius_multiplier = 1.0;
  double right_wheel_radius_multiplier = 1.0;
  // Standard deviations from those of yaw_scale and yaw_per_metre_rad
  // (their correlation neglected).
  double wheel_separation_multiplier_stddev = 0.0;
  double wheel_radius_multiplier_stddev = 0.0;  // of left and of right
  bool radius_difference_estimated = false;     // yaw_per_metre_rad was
  // A yaw-rate bias has no diff_drive_controller parameter (it comes from
  // a gyro-like heading drift, not from the wheels); non-zero when
  // estimated.
  double yaw_rate_bias_rad_s = 0.0;
};

// From the estimated odometry intrinsics: none unless yaw_scale was
// estimated (estimated[0]) and the nominal track is known
// (intrinsics.wheel_track_m > 0). stddev is [yaw_scale, yaw_per_metre_rad,
// yaw_rate_bias_rad_s], as SystematicsEstimate holds them.
std::optional<DiffDriveCorrections> DiffDriveCorrectionsFrom(
    const OdometryIntrinsics& intrinsics,
    const std::array<bool, 3>& estimated,
    const std::array<double, 3>& stddev);

struct RobotDescription {
  RobotFrameNames frames;
  // base_frame -> camera_frame, or base_frame -> camera_body_frame ->
  // camera_frame with the second one the fixed REP 103 rotation.
  std::vector<FrameTransform> transforms;
  // The camera height above the base frame was held at this value (planar
  // motion does not determine it), not estimated.
  bool height_held = true;
  double held_height_m = 0.0;
  std::optional<DiffDriveCorrections> diff_drive;
};

// base_from_optical is odomcal's odom_from_cam.
RobotDescription MakeRobotDescription(
    const Rigid3d& base_from_optical,
    const RobotFrameNames& frames,
    bool height_held,
    std::optional<DiffDriveCorrections> diff_drive);

// body_from_optical of REP 103 (URDF rpy -pi/2, 0, -pi/2).
Rigid3d BodyFromOpticalRotation();

// The files, each a complete text ending in a newline:
// - a URDF fragment: one <link> per child frame and one fixed <joint> per
//   transform, the held height named in a comment;
std::string UrdfFragment(const RobotDescription& robot);
// - `ros2 run tf2_ros static_transform_publisher --x ... --child-frame-id
//   ...`, one line per transform;
std::string Ros2StaticTransformCommands(const RobotDescription& robot);
// - `rosrun tf static_transform_publisher x y z qx qy qz qw frame_id
//   child_frame_id 100`, one line per transform;
std::string Ros1StaticTransformCommands(const RobotDescription& robot);
// - Autoware's sensors_calibration.yaml: parent: child: {x, y, z, roll,
//   pitch, yaw};
std::string AutowareSensorsCalibrationYaml(const RobotDescription& robot);
// - the diff_drive_controller parameters (empty without corrections).
std::string DiffDriveControllerYaml(const RobotDescription& robot);

// How the numbers are written: 12 significant digits, so that a value read
// back is within 1e-11 relative of the double; |value| < 1e-12 is "0".
std::string RobotNumber(double value);

}  // namespace odomcal
