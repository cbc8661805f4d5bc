#include "odomcal/plugin/cli/calibrate_command.h"

#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/input_plausibility.h"
#include "odomcal/adapters/systematics_warnings.h"
#include "odomcal/plugin/cli/command_flags.h"
#include "odomcal/plugin/cli/rig_calibration.h"
#include "odomcal/plugin/cli/rig_report.h"
#include "odomcal/plugin/colmap/odometry_inputs.h"
#include "odomcal/plugin/output/output_file.h"
#include "odomcal/plugin/output/output_guard.h"
#include "odomcal/plugin/report/robot_outputs.h"
#include "odomcal/solver/calibrate.h"
#include "odomcal/solver/repeatability.h"

#include <CLI/CLI.hpp>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <set>
#include <sstream>
#include <stdexcept>

namespace odomcal {

CalibrationRun RunCalibrationPipeline(const CalibrateInputs& inputs,
                                      const std::string& command) {
  inputs.association.Check();
  inputs.calibration.Check();
  inputs.robot_frames.Check();
  std::vector<Trajectory> cameras;
  for (const std::string& path : inputs.camera_paths) {
    cameras.push_back(ReadTumTrajectory(path, inputs.camera_time_unit));
  }
  return CalibrateTrajectories(
      cameras, ReadOdometryOf(inputs), inputs, command);
}

CalibrationRun CalibrateTrajectories(const std::vector<Trajectory>& cameras,
                                     const Trajectory& odometry,
                                     const CalibrateInputs& inputs,
                                     const std::string& command) {
  inputs.association.Check();
  inputs.calibration.Check();
  inputs.robot_frames.Check();
  CheckOdometrySpeed(odometry);

  CalibrationRun run;
  ReportContext& context = run.context;
  context.command = command;
  for (const Trajectory& camera : cameras) {
    context.camera_paths.push_back(camera.source);
  }
  context.odometry_path = odometry.source;
  context.odometry_format = inputs.odometry_format;
  context.camera_time_unit = TimeUnitName(inputs.camera_time_unit);
  // The unit the times were read in (a header suffix overrides the flag).
  context.odometry_time_unit =
      TimeUnitName(odometry.time_unit.value_or(inputs.odometry_time_unit));
  context.association_options = inputs.association;
  context.calibration_options = inputs.calibration;
  context.systematics_options = inputs.systematics;
  context.robot_frames = inputs.robot_frames;
  context.flag_echo = CalibrationFlagsEcho(inputs.association,
                                           inputs.calibration,
                                           inputs.systematics,
                                           inputs.robot_frames);
  // The association and calibration, once or in the systematics loop.
  const auto calibrate = [&](const AssociationResult& association) {
    if (association.num_usable_camera_poses == 0) {
      throw FormatError(
          "no camera timestamp falls inside the odometry (" +
          std::to_string(association.num_outside_odometry_span) +
          " outside its span, " +
          std::to_string(association.num_in_odometry_gaps) + " in gaps): " +
          TimeSpansText(cameras,
                        "",
                        association.camera_time_offset_ns,
                        odometry,
                        association.camera_time_offset_ns !=
                            inputs.association.camera_time_offset_ns) +
          "; check the time units and --camera_time_offset_s");
    }
    CheckRotationAngleUnits(association.pairs, odometry.source);
    run.result = CalibrateOdomCam(association.pairs, inputs.calibration);
    return std::make_pair(&association.pairs, &run.result);
  };
  context.systematics = EstimateSystematics(cameras,
                                            odometry,
                                            inputs.association,
                                            inputs.calibration,
                                            inputs.systematics,
                                            calibrate,
                                            &context.association);
  AddSystematicsWarnings(*context.systematics, &run.result);
  context.repeatability = CheckRepeatability(context.association.pairs,
                                             run.result,
                                             inputs.calibration,
                                             RepeatabilityOptions());
  if (const std::string warning = RepeatabilityWarning(*context.repeatability);
      !warning.empty()) {
    run.result.warnings.push_back(warning);
  }
  if (run.result.status == CalibrationStatus::kSuccess) {
    if (const auto warning =
            ExtrinsicDistanceWarning(run.result.odom_from_cam)) {
      run.result.warnings.push_back(*warning);
    }
  }
  if (context.association.num_outside_odometry_span > 0 ||
      context.association.num_in_odometry_gaps > 0) {
    std::ostringstream max_gap_s;  // "0.25", not std::to_string's "0.250000"
    max_gap_s << context.association.max_odometry_gap_s;
    run.result.warnings.push_back(
        std::to_string(context.association.num_outside_odometry_span +
                       context.association.num_in_odometry_gaps) +
        " camera poses were skipped: outside the odometry span or in gaps "
        "longer than " +
        max_gap_s.str() + " s");
  }
  return run;
}

void CheckCalibrationOutputs(const CalibrateInputs& inputs,
                             const std::string& json_path,
                             bool overwrite) {
  const std::string yaml_path = ReplaceExtension(json_path, ".yaml");
  GuardedPaths paths;
  for (const std::string& camera_path : inputs.camera_paths) {
    paths.inputs.push_back({camera_path, "--camera_poses"});
  }
  for (const NamedCameraPaths& camera :
       ParseNamedCameras(inputs.named_cameras)) {
    for (const std::string& camera_path : camera.paths) {
      paths.inputs.push_back({camera_path, "--camera"});
    }
  }
  paths.inputs.push_back({inputs.odometry_path, "--odometry"});
  paths.output_files = {{json_path, "--output"},
                        {yaml_path, "the YAML beside --output"}};
  for (const std::string& suffix : RobotOutputSuffixes()) {
    paths.output_files.push_back({RobotOutputPath(json_path, suffix),
                                  "the robot outputs beside --output"});
  }
  CheckOutputsApartFromInputs(paths);
  for (const auto& output : paths.output_files) {
    CheckOutputPath(output.path, overwrite);
  }
}

void WriteCalibrationOutputs(const CalibrationRun& run,
                             const std::string& json_path,
                             bool overwrite) {
  const std::string yaml_path = ReplaceExtension(json_path, ".yaml");
  CheckOutputPath(json_path, overwrite);
  CheckOutputPath(yaml_path, overwrite);
  WriteFileAtomically(
      json_path, CalibrationToJson(run.result, run.context).dump(2) + "\n");
  WriteFileAtomically(yaml_path, CalibrationToYaml(run.result));
  WriteRobotOutputsBeside(
      json_path, RobotDescriptionOf(run.result, run.context), overwrite);
}

void WriteRobotOutputsBeside(const std::string& json_path,
                             const std::optional<RobotDescription>& robot,
                             bool overwrite) {
  // The robot outputs of this result, and none of an earlier one (which
  // only --overwrite lets exist here).
  std::set<std::string> written;
  if (robot) {
    for (const RobotOutputFile& file : RobotOutputFiles(*robot)) {
      const std::string path = RobotOutputPath(json_path, file.suffix);
      CheckOutputPath(path, overwrite);
      WriteFileAtomically(path, file.text);
      written.insert(file.suffix);
    }
  }
  for (const std::string& suffix : RobotOutputSuffixes()) {
    if (written.count(suffix) == 0) {
      std::error_code ignored;
      std::filesystem::remove(RobotOutputPath(json_path, suffix), ignored);
    }
  }
}

int ExitCodeFor(const CalibrationResult& result) {
  return result.status == CalibrationStatus::kSuccess ? kExitSuccess
                                                      : kExitNotCalibrated;
}

namespace {

// `calibrate --camera NAME=PATH ...`: every camera against the odometry.
int RunRigCalibration(const CalibrateInputs& inputs,
                      const std::string& output_path,
                      bool overwrite,
                      bool quiet) {
  const std::vector<NamedCameraPaths> named =
      ParseNamedCameras(inputs.named_cameras);
  const int reference = ReferenceCameraIndex(named, inputs.reference_camera);
  inputs.association.Check();
  inputs.calibration.Check();
  inputs.robot_frames.Check();
  for (const NamedCameraPaths& camera : named) {
    RigCameraFrames(inputs.robot_frames, camera.name).Check();
  }
  std::vector<NamedCamera> cameras;
  for (const NamedCameraPaths& camera : named) {
    NamedCamera read{camera.name, {}};
    for (const std::string& path : camera.paths) {
      if (!std::filesystem::is_regular_file(path)) {
        throw std::invalid_argument("--camera " + camera.name + "=" + path +
                                    ": no such file");
      }
      read.segments.push_back(ReadTumTrajectory(path, inputs.camera_time_unit));
    }
    cameras.push_back(std::move(read));
  }
  const RigCalibrationRun rig = CalibrateRig(
      cameras, ReadOdometryOf(inputs), inputs, reference, "odomcal calibrate");
  WriteRigCalibrationOutputs(rig, output_path, overwrite);
  if (!quiet) {
    std::cout << RigCalibrationSummary(rig);
    std::cout << "  wrote " << output_path << " and "
              << ReplaceExtension(output_path, ".yaml");
    if (const auto robot = RigRobotDescription(rig)) {
      std::cout << "; for the robot";
      for (const RobotOutputFile& file : RobotOutputFiles(*robot)) {
        std::cout << " " << RobotOutputPath(output_path, file.suffix);
      }
    }
    std::cout << "\n";
  }
  if (rig.NumCalibrated() > 0 && !rig.Warnings().empty()) {
    std::cout << std::flush;
    for (const std::string& warning : rig.Warnings()) {
      std::cerr << "odomcal calibrate: warning: " << warning << "\n";
    }
  }
  return RigExitCode(rig);
}

}  // namespace

int RunCalibrate(int argc, char** argv) {
  CLI::App app{
      "Calibrates the camera-to-odometry extrinsic (odom_from_cam) and the "
      "metric scale from a camera trajectory and wheel odometry.",
      "odomcal calibrate"};
  CalibrateInputs inputs;
  std::string output_path;
  bool overwrite = false;
  bool quiet = false;
  CLI::Option* camera_poses =
      app.add_option("--camera_poses",
                     inputs.camera_paths,
                     "camera trajectory, TUM 'timestamp tx ty tz qx qy qz "
                     "qw', world_from_cam; repeat for SfM segments with their "
                     "own scale")
          ->check(CLI::ExistingFile);
  CLI::Option* camera =
      app.add_option("--camera",
                     inputs.named_cameras,
                     "NAME=PATH: a camera of a rig and its trajectory (as "
                     "--camera_poses); repeat for every camera, each "
                     "calibrated against the odometry; the same NAME again "
                     "adds a segment")
          ->excludes(camera_poses);
  app.add_option("--reference_camera",
                 inputs.reference_camera,
                 "with --camera: the camera whose extrinsic is the result's "
                 "top-level odom_from_cam (default: the first)")
      ->needs(camera);
  app.add_option("--odometry",
                 inputs.odometry_path,
                 "wheel odometry: CSV 'timestamp,x,y,yaw' (m, rad) or TUM "
                 "origin_from_odom")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--output",
                 output_path,
                 "result JSON; a YAML file and the robot outputs (URDF, tf, "
                 "Autoware) are written beside it")
      ->required();
  app.add_flag("--overwrite", overwrite, "replace existing output files");
  app.add_flag("--quiet", quiet, "print only errors");
  AddCalibrationFlags(&app, &inputs);

  if (const auto exit_code = ParseFlags(&app, argc, argv)) {
    return *exit_code;
  }
  return RunReportingErrors(app, [&]() -> int {
    if (inputs.camera_paths.empty() && inputs.named_cameras.empty()) {
      throw std::invalid_argument("--camera_poses or --camera is required");
    }
    CheckCalibrationOutputs(inputs, output_path, overwrite);
    if (!inputs.named_cameras.empty()) {
      return RunRigCalibration(inputs, output_path, overwrite, quiet);
    }
    const CalibrationRun run =
        RunCalibrationPipeline(inputs, "odomcal calibrate");
    WriteCalibrationOutputs(run, output_path, overwrite);
    if (!quiet) {
      std::cout << CalibrationSummary(run.result, run.context);
      std::cout << "  wrote " << output_path << " and "
                << ReplaceExtension(output_path, ".yaml");
      if (const auto robot = RobotDescriptionOf(run.result, run.context)) {
        std::cout << "; for the robot";
        for (const RobotOutputFile& file : RobotOutputFiles(*robot)) {
          std::cout << " " << RobotOutputPath(output_path, file.suffix);
        }
      }
      std::cout << "\n";
    }
    return ExitCodeFor(run.result);
  });
}

}  // namespace odomcal
