#include "odomcal/plugin/report/robot_outputs.h"

#include "odomcal/plugin/report/svg_plot.h"
#include "odomcal/solver/format_number.h"

#include <filesystem>
#include <sstream>

namespace odomcal {

using json = nlohmann::json;

std::optional<RobotDescription> RobotDescriptionOf(
    const CalibrationResult& result, const ReportContext& context) {
  const Observability& o = result.observability;
  constexpr Determination kEstimated = Determination::kEstimated;
  if (!result.IsSuccess() || o.rotation != kEstimated ||
      o.translation_x != kEstimated || o.translation_y != kEstimated) {
    return std::nullopt;
  }
  std::optional<DiffDriveCorrections> diff_drive;
  if (context.systematics) {
    OdometryIntrinsics intrinsics = context.systematics->intrinsics;
    intrinsics.wheel_track_m = context.systematics_options.wheel_track_m;
    diff_drive =
        DiffDriveCorrectionsFrom(intrinsics,
                                 context.systematics->intrinsics_estimated,
                                 context.systematics->intrinsics_stddev);
  }
  return MakeRobotDescription(result.odom_from_cam,
                              context.robot_frames,
                              o.translation_z != kEstimated &&
                                  !result.translation_z_prior.moved_by_data,
                              diff_drive);
}

json RobotToJson(const std::optional<RobotDescription>& robot) {
  if (!robot) return nullptr;
  json transforms = json::array();
  for (const FrameTransform& transform : robot->transforms) {
    const Eigen::Quaterniond q =
        WithPositiveScalar(transform.parent_from_child.rotation.normalized());
    const Eigen::Vector3d& t = transform.parent_from_child.translation;
    const Eigen::Vector3d rpy = RollPitchYaw(q);
    transforms.push_back({{"parent", transform.parent},
                          {"child", transform.child},
                          {"translation_m", {t.x(), t.y(), t.z()}},
                          {"quaternion_xyzw", {q.x(), q.y(), q.z(), q.w()}},
                          {"rpy_rad", {rpy.x(), rpy.y(), rpy.z()}}});
  }
  json diff_drive = nullptr;
  if (robot->diff_drive) {
    const DiffDriveCorrections& c = *robot->diff_drive;
    diff_drive = {
        {"wheel_separation_multiplier", c.wheel_separation_multiplier},
        {"left_wheel_radius_multiplier", c.left_wheel_radius_multiplier},
        {"right_wheel_radius_multiplier", c.right_wheel_radius_multiplier},
        {"wheel_separation_multiplier_stddev",
         c.wheel_separation_multiplier_stddev},
        {"wheel_radius_multiplier_stddev", c.wheel_radius_multiplier_stddev},
        {"radius_difference_estimated", c.radius_difference_estimated},
        {"yaw_rate_bias_rad_s", c.yaw_rate_bias_rad_s},
        {"parameters_yaml", DiffDriveControllerYaml(*robot)},
    };
  }
  const RobotFrameNames& frames = robot->frames;
  return {
      {"conventions",
       {{"transform", "x_parent = parent_from_child * x_child"},
        {"quaternion", "Hamilton, order x, y, z, w (ROS)"},
        {"rpy", "URDF fixed axes: R = Rz(yaw) * Ry(pitch) * Rx(roll), radians"},
        {"camera_frame", "optical: x right, y down, z forward"}}},
      {"base_frame", frames.base_frame},
      {"camera_frame", frames.camera_frame},
      {"camera_body_frame",
       frames.camera_body_frame.empty() ? json(nullptr)
                                        : json(frames.camera_body_frame)},
      {"transforms", transforms},
      {"height_held", robot->height_held},
      {"held_height_m",
       robot->height_held ? json(robot->held_height_m) : json(nullptr)},
      {"urdf", UrdfFragment(*robot)},
      {"ros2_static_transform_publisher", Ros2StaticTransformCommands(*robot)},
      {"ros1_static_transform_publisher", Ros1StaticTransformCommands(*robot)},
      {"autoware_sensors_calibration", AutowareSensorsCalibrationYaml(*robot)},
      {"diff_drive_controller", diff_drive},
  };
}

std::vector<std::string> RobotOutputSuffixes() {
  return {".urdf",
          "_tf_ros2.sh",
          "_tf_ros1.sh",
          "_autoware.yaml",
          "_diff_drive.yaml"};
}

std::vector<RobotOutputFile> RobotOutputFiles(const RobotDescription& robot) {
  std::vector<RobotOutputFile> files = {
      {".urdf", UrdfFragment(robot)},
      {"_tf_ros2.sh", Ros2StaticTransformCommands(robot)},
      {"_tf_ros1.sh", Ros1StaticTransformCommands(robot)},
      {"_autoware.yaml", AutowareSensorsCalibrationYaml(robot)},
  };
  if (robot.diff_drive) {
    files.push_back({"_diff_drive.yaml", DiffDriveControllerYaml(robot)});
  }
  return files;
}

std::string RobotOutputPath(const std::string& result_path,
                            const std::string& suffix) {
  return std::filesystem::path(result_path).replace_extension().string() +
         suffix;
}

std::string RobotUseItHtml(const std::optional<RobotDescription>& robot) {
  std::ostringstream html;
  html << "<h2>Use it</h2>\n";
  if (!robot) {
    html << "<p>No robot outputs: only a calibration that succeeded with "
            "rotation, x and y estimated is written for a robot.</p>\n";
    return html.str();
  }
  html << "<p>The extrinsic in the forms robots load, also written beside "
          "calibration.json. Frames: "
       << EscapeMarkup(robot->frames.base_frame);
  // A chain as one line; a rig's cameras each from the base frame.
  std::string previous = robot->frames.base_frame;
  for (const FrameTransform& transform : robot->transforms) {
    if (transform.parent != previous) {
      html << ", " << EscapeMarkup(transform.parent);
    }
    html << " &rarr; " << EscapeMarkup(transform.child);
    previous = transform.child;
  }
  html << " (the camera frame is the optical frame: x right, y down, z "
          "forward). Each transform maps child to parent coordinates, as a "
          "URDF joint's origin and a tf transform do.";
  if (robot->height_held) {
    html << " <strong>The camera height z = "
         << EscapeMarkup(FormatNumber(robot->held_height_m))
         << " m is the value of --fixed_translation_z_m, not measured</strong>"
            ": planar driving does not determine it.";
  }
  html << "</p>\n";
  int index = 0;
  for (const RobotOutputFile& file : RobotOutputFiles(*robot)) {
    const std::string id = "robot-output-" + std::to_string(index++);
    html << "<h3>calibration" << EscapeMarkup(file.suffix)
         << " <button type=\"button\" onclick=\"odomcalCopy('" << id
         << "', this)\">copy</button></h3>\n<pre id=\"" << id << "\">"
         << EscapeMarkup(file.text) << "</pre>\n";
  }
  // Copies a <pre>'s text; file:// pages may lack the clipboard API.
  html << "<script>function odomcalCopy(id, button) {"
          "const text = document.getElementById(id).textContent;"
          "const done = () => { button.textContent = 'copied'; };"
          "if (navigator.clipboard) {"
          "navigator.clipboard.writeText(text).then(done, () => {});"
          "return; }"
          "const range = document.createRange();"
          "range.selectNodeContents(document.getElementById(id));"
          "const selection = window.getSelection();"
          "selection.removeAllRanges(); selection.addRange(range);"
          "if (document.execCommand('copy')) done(); }</script>\n";
  return html.str();
}

std::string RobotSummary(const RobotDescription& robot) {
  std::ostringstream out;
  out << "  Robot (" << robot.frames.base_frame;
  for (const FrameTransform& transform : robot.transforms) {
    out << " -> " << transform.child;
  }
  out << "):\n";
  for (const FrameTransform& transform : robot.transforms) {
    const Eigen::Vector3d& t = transform.parent_from_child.translation;
    const Eigen::Vector3d rpy =
        RollPitchYaw(transform.parent_from_child.rotation);
    out << "    URDF origin " << transform.parent << " -> " << transform.child
        << ": xyz=\"" << RobotNumber(t.x()) << " " << RobotNumber(t.y()) << " "
        << RobotNumber(t.z()) << "\" rpy=\"" << RobotNumber(rpy.x()) << " "
        << RobotNumber(rpy.y()) << " " << RobotNumber(rpy.z()) << "\"\n";
  }
  std::istringstream commands(Ros2StaticTransformCommands(robot));
  std::string line;
  while (std::getline(commands, line)) {
    if (!line.empty() && line[0] != '#') out << "    " << line << "\n";
  }
  if (robot.height_held) {
    out << "    z = " << FormatNumber(robot.held_height_m)
        << " m is held, not measured (--fixed_translation_z_m)\n";
  }
  if (robot.diff_drive) {
    const DiffDriveCorrections& c = *robot.diff_drive;
    out << "    diff_drive_controller: wheel_separation_multiplier "
        << FormatRounded(c.wheel_separation_multiplier, 5)
        << ", left_wheel_radius_multiplier "
        << FormatRounded(c.left_wheel_radius_multiplier, 5)
        << ", right_wheel_radius_multiplier "
        << FormatRounded(c.right_wheel_radius_multiplier, 5)
        << " (their mean held at 1)\n";
  }
  return out.str();
}

}  // namespace odomcal
