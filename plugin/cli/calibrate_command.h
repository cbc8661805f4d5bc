// `odomcal calibrate`: extrinsic and metric scale from a camera trajectory
// (TUM, world_from_cam, one file per SfM segment) and wheel odometry (TUM or
// CSV timestamp,x,y,yaw).
#pragma once

#include "odomcal/adapters/association.h"
#include "odomcal/adapters/robot_description.h"
#include "odomcal/adapters/systematics_estimation.h"
#include "odomcal/adapters/timestamp.h"
#include "odomcal/adapters/trajectory_io.h"
#include "odomcal/plugin/cli/command_line.h"
#include "odomcal/plugin/report/calibration_report.h"
#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/calibration_result.h"

#include <optional>
#include <string>
#include <vector>

namespace odomcal {

struct CalibrateInputs {
  std::vector<std::string> camera_paths;
  // --camera NAME=PATH values (rig_calibration.h): each named camera
  // calibrated against the odometry; instead of camera_paths.
  std::vector<std::string> named_cameras;
  std::string reference_camera;  // --reference_camera; empty: the first
  std::string odometry_path;
  OdometryFormat odometry_format = OdometryFormat::kAuto;
  TimeUnit camera_time_unit = TimeUnit::kSeconds;
  TimeUnit odometry_time_unit = TimeUnit::kSeconds;
  bool odometry_time_unit_given = false;  // by the user, not the default
  AssociationOptions association;
  CalibrationOptions calibration;
  // Clock offset and odometry intrinsics estimated with the extrinsic.
  SystematicsEstimationOptions systematics;
  // The frames the robot outputs name (robot_description.h).
  RobotFrameNames robot_frames;
};

struct CalibrationRun {
  CalibrationResult result;
  ReportContext context;
};

// Reads the inputs, associates them and calibrates. Throws FormatError for
// unreadable/malformed files and std::invalid_argument for bad options.
CalibrationRun RunCalibrationPipeline(const CalibrateInputs& inputs,
                                      const std::string& command);

// The pipeline after reading: checks, association, calibration and warnings,
// on trajectories read or built elsewhere (the Python module's arrays).
// Uses inputs' options and time units, not its paths: the report names each
// trajectory by its `source`. Throws like RunCalibrationPipeline.
CalibrationRun CalibrateTrajectories(const std::vector<Trajectory>& cameras,
                                     const Trajectory& odometry,
                                     const CalibrateInputs& inputs,
                                     const std::string& command);

// Checks <output>.json and the <output>.yaml beside it before any work: apart
// from the inputs and from each other (output_guard.h), and replaceable
// (CheckOutputPath). Throws OutputError.
void CheckCalibrationOutputs(const CalibrateInputs& inputs,
                             const std::string& json_path,
                             bool overwrite);

// The robot outputs of `robot` beside <output>.json (RobotOutputPath), each
// checked (CheckOutputPath); those of an earlier result that `robot` does
// not have are removed.
void WriteRobotOutputsBeside(const std::string& json_path,
                             const std::optional<RobotDescription>& robot,
                             bool overwrite);

// Writes <output>.json and <output>.yaml atomically (both checked first).
void WriteCalibrationOutputs(const CalibrationRun& run,
                             const std::string& json_path,
                             bool overwrite);

// Exit code for a finished calibration.
int ExitCodeFor(const CalibrationResult& result);

int RunCalibrate(int argc, char** argv);

}  // namespace odomcal
