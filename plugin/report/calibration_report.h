// The calibration's outputs: result JSON (the public schema documented in
// docs/result_schema.md), an OpenCV FileStorage YAML with the same core
// numbers, and the human summary printed by the CLI.
#pragma once

#include "odomcal/adapters/association.h"
#include "odomcal/adapters/robot_description.h"
#include "odomcal/adapters/systematics_estimation.h"
#include "odomcal/adapters/trajectory_io.h"
#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/calibration_result.h"
#include "odomcal/solver/repeatability.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace odomcal {

// Everything about a run that the report echoes besides the result.
// clang-tidy 14 reports its implicit special members as possibly throwing
// where they must not; they copy and move standard containers and JSON.
struct ReportContext {  // NOLINT(bugprone-exception-escape)
  std::string command;  // e.g. "odomcal calibrate"
  std::vector<std::string> camera_paths;
  std::string odometry_path;
  OdometryFormat odometry_format = OdometryFormat::kAuto;  // as given
  std::string camera_time_unit;
  std::string odometry_time_unit;
  AssociationOptions association_options;
  AssociationResult association;  // counts; pairs are not echoed
  CalibrationOptions calibration_options;
  SystematicsEstimationOptions systematics_options;
  // The values of the command's flags, {"inputs": {...}, "options": {...}},
  // written into the result's `inputs` (after the paths and units above) and
  // `options`, as made from the option tables (CalibrationFlagsEcho in
  // cli_flags.h, ProjectFlagsEcho, RunFlagsEcho). Null (the default): the
  // echo of association_options, calibration_options and
  // systematics_options.
  nlohmann::json flag_echo;
  // Clock offset and odometry intrinsics, when the command estimated them
  // (JSON camera_time_offset_s, odometry_intrinsics, diagnostics.time_offset).
  std::optional<SystematicsEstimate> systematics;
  // The frames the robot outputs name (JSON `robot`, RobotOutputFiles).
  RobotFrameNames robot_frames;
  // The calibration repeated on time blocks (JSON `repeatability`).
  std::optional<Repeatability> repeatability;
};

constexpr int kResultSchemaVersion = 1;

nlohmann::json CalibrationToJson(const CalibrationResult& result,
                                 const ReportContext& context);

// A transform as the JSON's odom_from_cam holds it: "matrix" (4 x 4, rows),
// "quaternion_wxyz", "roll_pitch_yaw_deg" (null unless the rotation is
// determined) and "translation_m" (each axis null unless determined).
nlohmann::json TransformToJson(const Rigid3d& transform,
                               bool rotation_determined,
                               bool x_determined,
                               bool y_determined,
                               bool z_determined);

// OpenCV FileStorage YAML ("%YAML:1.0"), readable with cv::FileStorage.
std::string CalibrationToYaml(const CalibrationResult& result);

// The association in one line: "281 camera poses: 281 used, 0 outside the
// odometry's span, 0 in its gaps (> 0.658 s, automatic); odometry at 3.8 Hz;
// 281 keyframes, 280 motion pairs".
std::string AssociationSummary(const AssociationResult& association);

// With automatic keyframe thresholds: the spacing used and the camera pose
// drift test that chose it, for the summary's keyframes line; else "".
std::string KeyframeSpacingSummary(const AssociationResult& association);

// Multi-line human summary: status, rotation as roll/pitch/yaw and
// quaternion, translation in cm with 3-sigma bounds, scales, residuals,
// warnings.
std::string CalibrationSummary(const CalibrationResult& result,
                               const ReportContext& context);

}  // namespace odomcal
