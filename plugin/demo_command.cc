#include "odomcal/plugin/demo_command.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "odomcal/adapters/format_error.h"
#include "odomcal/datasets/drive_simulator.h"
#include "odomcal/plugin/calibrate_command.h"
#include "odomcal/plugin/cli_flags.h"
#include "odomcal/plugin/output_file.h"

namespace odomcal {
namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

nlohmann::json GroundTruthJson(const SimulatedDrive& drive,
                               const DriveSimulatorOptions& options) {
  const Eigen::Quaterniond& q = drive.odom_from_cam.rotation;
  const Eigen::Vector3d& t = drive.odom_from_cam.translation;
  return {
      {"odom_from_cam",
       {{"quaternion_wxyz", {q.w(), q.x(), q.y(), q.z()}},
        {"translation_m", {t.x(), t.y(), t.z()}}}},
      {"metric_scale", drive.metric_scale},
      {"simulation",
       {{"seed", options.seed},
        {"duration_s", options.duration_s},
        {"odometry_rate_hz", options.odometry_rate_hz},
        {"camera_rate_hz", options.camera_rate_hz},
        {"wheel_scale_error_left", options.wheel_scale_error_left},
        {"wheel_scale_error_right", options.wheel_scale_error_right},
        {"yaw_rate_bias_radps", options.yaw_rate_bias_radps},
        {"camera_rotation_noise_deg", options.camera_rotation_noise_deg},
        {"camera_position_noise", options.camera_position_noise}}},
  };
}

}  // namespace

int RunDemo(int argc, char** argv) {
  CLI::App app{
      "Simulates a robot drive with a known camera mount, calibrates it from "
      "the written files and compares with the ground truth.",
      "odomcal demo"};
  std::string workspace = "odomcal_demo";
  DriveSimulatorOptions simulation;
  simulation.seed = 1;
  simulation.duration_s = 120.0;
  // Realistic wheel odometry and SfM errors.
  simulation.wheel_scale_error_left = 0.003;
  simulation.wheel_scale_error_right = -0.002;
  simulation.yaw_rate_bias_radps = 0.002;
  simulation.camera_rotation_noise_deg = 0.02;
  simulation.camera_position_noise = 0.002;
  app.add_option("--workspace_path", workspace,
                 "folder for the demo's inputs and outputs (its files are "
                 "replaced on every run)")
      ->capture_default_str();
  app.add_option("--seed", simulation.seed, "simulation seed")
      ->capture_default_str();
  app.add_option("--duration_s", simulation.duration_s, "drive duration")
      ->check(CLI::Range(5.0, 3600.0))
      ->capture_default_str();
  CalibrateInputs inputs;
  CalibrationFlags flags;
  AddCalibrationFlags(&app, &inputs, &flags);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return kExitSuccess;
  } catch (const CLI::ParseError& error) {
    std::cerr << "odomcal demo: error: " << error.what() << "\n";
    return kExitBadInput;
  }

  try {
    FinishCalibrationFlags(flags, &inputs);
    std::error_code error;
    std::filesystem::create_directories(workspace, error);
    if (error || !std::filesystem::is_directory(workspace)) {
      throw OutputError(workspace + ": cannot create the workspace folder");
    }
    const std::filesystem::path root(workspace);
    std::cout << "[1/3] simulating a " << simulation.duration_s
              << " s drive (seed " << simulation.seed << ")\n";
    const SimulatedDrive drive = SimulateDrive(simulation);
    const std::string camera_path = (root / "camera.tum").string();
    const std::string odometry_path = (root / "odometry.csv").string();
    const std::string truth_path = (root / "ground_truth.json").string();
    WriteTumTrajectory(drive.camera, camera_path);
    WriteOdometryCsv(drive.odometry, odometry_path);
    WriteFileAtomically(truth_path,
                        GroundTruthJson(drive, simulation).dump(2) + "\n");
    std::cout << "      wrote " << camera_path << " (" << drive.camera.poses.size()
              << " poses), " << odometry_path << " ("
              << drive.odometry.poses.size() << " samples), " << truth_path
              << "\n";

    std::cout << "[2/3] calibrating from the written files\n";
    inputs.camera_paths = {camera_path};
    inputs.odometry_path = odometry_path;
    inputs.calibration.fixed_translation_z_m = drive.odom_from_cam.translation.z();
    const CalibrationRun run = RunCalibrationPipeline(inputs, "odomcal demo");
    const std::string result_path = (root / "calibration.json").string();
    WriteCalibrationOutputs(run, result_path, /*overwrite=*/true);
    std::cout << CalibrationSummary(run.result, run.context);
    std::cout << "      wrote " << result_path << " and "
              << ReplaceExtension(result_path, ".yaml") << "\n";

    std::cout << "[3/3] comparison with the ground truth\n";
    const CalibrationResult& result = run.result;
    if (!result.has_estimate) {
      std::cout << "      no estimate to compare\n";
      return ExitCodeFor(result);
    }
    const double rotation_error_deg =
        RotationAngle(result.odom_from_cam.rotation.conjugate() *
                      drive.odom_from_cam.rotation) *
        kRadToDeg;
    const Eigen::Vector3d translation_error =
        result.odom_from_cam.translation - drive.odom_from_cam.translation;
    const double scale_error =
        result.metric_scales[0] / drive.metric_scale - 1.0;
    std::printf("      rotation error     %8.4f deg\n", rotation_error_deg);
    std::printf("      translation error  x %+7.2f mm, y %+7.2f mm (z fixed)\n",
                1000.0 * translation_error.x(), 1000.0 * translation_error.y());
    std::printf("      scale error        %+8.4f %%\n", 100.0 * scale_error);
    return ExitCodeFor(result);
  } catch (const FormatError& error) {
    std::cerr << "odomcal demo: error: " << error.what() << "\n";
  } catch (const OutputError& error) {
    std::cerr << "odomcal demo: error: " << error.what() << "\n";
  } catch (const std::invalid_argument& error) {
    std::cerr << "odomcal demo: error: " << error.what() << "\n";
  }
  return kExitBadInput;
}

}  // namespace odomcal
