#include "odomcal/plugin/cli/demo_command.h"

#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/timestamp.h"
#include "odomcal/datasets/rendering/dataset_presets.h"
#include "odomcal/datasets/rendering/rendered_dataset.h"
#include "odomcal/datasets/simulation/drive_simulator.h"
#include "odomcal/plugin/cli/calibrate_command.h"
#include "odomcal/plugin/cli/command_flags.h"
#include "odomcal/plugin/cli/run_command.h"
#include "odomcal/plugin/colmap/colmap_runner.h"
#include "odomcal/plugin/output/output_file.h"
#include "odomcal/plugin/output/output_folder.h"
#include "odomcal/plugin/report/joint_adjustment_report.h"
#include "odomcal/plugin/report/robot_outputs.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/format_number.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

namespace odomcal {
namespace {

nlohmann::json SimulatedGroundTruthJson(const SimulatedDrive& drive,
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
        {"camera_position_noise", options.camera_position_noise},
        {"ground_tilt_deg", options.ground_tilt_deg},
        {"ground_wavelength_m", options.ground_wavelength_m},
        {"wheel_track_error", options.wheel_track_error},
        {"camera_time_offset_s", options.camera_time_offset_s},
        {"profile",
         options.profile == DriveProfile::kSmooth ? "smooth" : "manoeuvres"}}},
  };
}

// The trajectory-only demo: simulated drive -> TUM/CSV files -> calibrate.
// With `wheel_travels` the odometry is written as the drive's wheel travels
// (wheels.csv, timestamp,left_m,right_m: no yaw-rate bias, that is a gyro's)
// and calibrated from them with --wheel_track_m.
int RunSimulatedDemo(const std::string& workspace,
                     const DriveSimulatorOptions& simulation,
                     bool wheel_travels,
                     CalibrateInputs inputs) {
  // Every run replaces the demo's own files (and only those).
  std::vector<std::string> entries = {"camera.tum",
                                      "odometry.csv",
                                      "wheels.csv",
                                      "ground_truth.json",
                                      "calibration.json",
                                      "calibration.yaml"};
  for (const std::string& suffix : RobotOutputSuffixes()) {
    entries.push_back("calibration" + suffix);
  }
  ClaimOutputFolder(workspace, entries, ExistingOutputs::kReplaceOwn);
  const std::filesystem::path root(workspace);
  std::cout << "[1/3] simulating a " << simulation.duration_s
            << " s drive (seed " << simulation.seed << ")\n";
  const SimulatedDrive drive = SimulateDrive(simulation);
  const std::string camera_path = (root / "camera.tum").string();
  const std::string odometry_path =
      (root / (wheel_travels ? "wheels.csv" : "odometry.csv")).string();
  const std::string truth_path = (root / "ground_truth.json").string();
  WriteTumTrajectory(drive.camera, camera_path);
  if (wheel_travels) {
    WriteWheelTravelCsv(drive.wheel_travels, odometry_path);
  } else {
    WriteOdometryCsv(drive.odometry, odometry_path);
  }
  WriteFileAtomically(
      truth_path, SimulatedGroundTruthJson(drive, simulation).dump(2) + "\n");
  std::cout << "      wrote " << camera_path << " ("
            << drive.camera.poses.size() << " poses), " << odometry_path << " ("
            << drive.odometry.poses.size() << " samples), " << truth_path
            << "\n";

  std::cout << "[2/3] calibrating from the written files\n";
  inputs.camera_paths = {camera_path};
  inputs.odometry_path = odometry_path;
  inputs.calibration.fixed_translation_z_m =
      drive.odom_from_cam.translation.z();
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
  const double scale_error = result.metric_scales[0] / drive.metric_scale - 1.0;
  std::printf("      rotation error     %8.4f deg\n", rotation_error_deg);
  std::printf("      translation error  x %+7.2f mm, y %+7.2f mm (z fixed)\n",
              1000.0 * translation_error.x(),
              1000.0 * translation_error.y());
  std::printf("      scale error        %+8.4f %%\n", 100.0 * scale_error);
  if (run.context.systematics) {
    // The simulator's encoders report travel * (1 + e) over a track of
    // 0.4 m * (1 + track error) and add a yaw-rate bias b: the correction of
    // odometry_intrinsics.h is yaw_scale = (k_l + k_r) / (2 k_t), yaw_per_metre
    // = (k_r - k_l) / (k_t 0.4 m), yaw_rate_bias = -yaw_scale * b with
    // k = 1 / (1 + e).
    const SystematicsEstimate& estimate = *run.context.systematics;
    const double k_left = 1.0 / (1.0 + simulation.wheel_scale_error_left);
    const double k_right = 1.0 / (1.0 + simulation.wheel_scale_error_right);
    const double k_track = 1.0 + simulation.wheel_track_error;
    const double yaw_scale = 0.5 * (k_left + k_right) / k_track;
    std::printf("      time offset error  %+8.3f ms\n",
                1e3 * (NsToSeconds(estimate.camera_time_offset_ns) -
                       simulation.camera_time_offset_s));
    std::printf("      yaw_scale error    %+8.4f %%\n",
                100.0 * (estimate.intrinsics.yaw_scale / yaw_scale - 1.0));
    std::printf("      yaw_per_metre error %+8.5f rad/m\n",
                estimate.intrinsics.yaw_per_metre_rad -
                    (k_right - k_left) / (k_track * 0.4));
    const double odometry_bias =
        wheel_travels ? 0.0 : simulation.yaw_rate_bias_radps;
    std::printf(
        "      yaw_rate_bias error %+8.6f rad/s\n",
        estimate.intrinsics.yaw_rate_bias_rad_s + yaw_scale * odometry_bias);
    if (estimate.right_over_left) {
      std::printf(
          "      right_over_left error %+8.4f %% (3 sigma %.4f %%)\n",
          100.0 * (*estimate.right_over_left / (k_right / k_left) - 1.0),
          300.0 * estimate.right_over_left_stddev / (k_right / k_left));
    }
  }
  return ExitCodeFor(result);
}

std::string ReadTextFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream buffer;
  buffer << file.rdbuf();
  return buffer.str();
}

// Pairwise-distance scale of `estimated` relative to `truth` (same images):
// 1 when the metric model has the true size.
double RelativeModelScale(const std::vector<Eigen::Vector3d>& estimated,
                          const std::vector<Eigen::Vector3d>& truth) {
  double numerator = 0.0, denominator = 0.0;
  for (size_t i = 0; i < truth.size(); ++i) {
    for (size_t j = i + 1; j < truth.size(); ++j) {
      const double d_true = (truth[i] - truth[j]).norm();
      numerator += (estimated[i] - estimated[j]).norm() * d_true;
      denominator += d_true * d_true;
    }
  }
  return denominator > 0.0 ? numerator / denominator : std::nan("");
}

// The main job: rendered scene -> COLMAP -> calibration -> ground truth.
int RunRenderedDemo(const std::string& workspace,
                    const std::string& preset,
                    uint64_t seed,
                    const CalibrateInputs& calibrate) {
  namespace fs = std::filesystem;
  const fs::path root(workspace);
  const fs::path dataset_dir = root / "dataset";
  // Every run replaces the demo's own dataset/ and run/ (and only those).
  ClaimOutputFolder(
      workspace, {"dataset", "run"}, ExistingOutputs::kReplaceOwn);
  std::cout << "[demo] rendering preset '" << preset << "' (seed " << seed
            << ") into " << dataset_dir.string() << std::endl;
  const RenderedDataset dataset =
      SimulateRenderedDataset(MakeDatasetPreset(preset, seed));
  const std::string truth_json = GroundTruthJson(dataset);
  if (ReadTextFile((dataset_dir / "ground_truth.json").string()) ==
      truth_json) {
    std::cout << "       already rendered; reusing it" << std::endl;
  } else {
    RemoveOwnedOutput(workspace, "dataset");
    WriteRenderedDataset(
        dataset, dataset_dir.string(), [](size_t done, size_t total) {
          if (done == total || done % 10 == 0) {
            std::cout << "       rendered " << done << "/" << total << " images"
                      << std::endl;
          }
        });
  }

  ReconstructionOptions settings;
  settings.image_path = (dataset_dir / "images").string();
  settings.workspace_path = (root / "run").string();
  settings.camera_model = dataset.options.camera.ColmapModelName();
  for (const double value : dataset.options.camera.ColmapParams()) {
    char text[32];
    std::snprintf(text, sizeof(text), "%.17g", value);
    settings.camera_params +=
        (settings.camera_params.empty() ? "" : ",") + std::string(text);
  }
  ColmapCalibrationInputs& inputs = settings.project;
  inputs.odometry_path = (dataset_dir / "odometry.csv").string();
  inputs.image_timestamps_path =
      (dataset_dir / "image_timestamps.csv").string();
  inputs.association = calibrate.association;
  inputs.calibration = calibrate.calibration;
  inputs.systematics = calibrate.systematics;
  // z, unobservable from planar motion, comes from the floor under the
  // metric model (the rendered odometry frame lies on the floor, REP 120's
  // base_footprint: --odometry_height_m 0). The demo gives the robot's
  // nominal wheel track, as a user would their robot's, so that unequal
  // wheels are corrected in turns (docs/systematics.md).
  if (inputs.systematics.wheel_track_m == 0.0) {
    inputs.systematics.wheel_track_m =
        dataset.options.odometry_noise.wheel_base_m;
  }
  std::cout << "[demo] odomcal run --image_path " << settings.image_path
            << " --odometry " << inputs.odometry_path << " --image_timestamps "
            << inputs.image_timestamps_path << " --camera_model "
            << settings.camera_model << " --camera_params "
            << settings.camera_params << " --wheel_track_m "
            << FormatNumber(inputs.systematics.wheel_track_m)
            << " --workspace_path " << settings.workspace_path << std::endl;
  const RunOutcome run = RunAndWriteOutputs(settings, "odomcal demo");
  const CalibrationResult& result = run.calibration.check.result;
  std::cout << CalibrationSummary(result, run.context)
            << JointAdjustmentSummary(run.calibration);

  std::cout << "[demo] comparison with the ground truth\n";
  if (!result.has_estimate) {
    std::cout << "       no estimate to compare\n";
    return ExitCodeFor(result);
  }
  const Rigid3d& truth = dataset.options.odom_from_cam;
  const double rotation_error_deg =
      RotationAngle(result.odom_from_cam.rotation.conjugate() *
                    truth.rotation) *
      kRadToDeg;
  const Eigen::Vector3d translation_error =
      result.odom_from_cam.translation - truth.translation;
  std::printf("       rotation error     %8.4f deg\n", rotation_error_deg);
  std::printf(
      "       translation error  x %+7.2f mm, y %+7.2f mm, z %+7.2f mm (%s)\n",
      1000.0 * translation_error.x(),
      1000.0 * translation_error.y(),
      1000.0 * translation_error.z(),
      result.observability.translation_z_source ==
              TranslationZSource::kFloorPlane
          ? "z from the floor plane"
          : "z held: not from the floor");
  // The metric model against the true camera positions.
  std::map<std::string, Eigen::Vector3d> true_position;
  for (const RenderedFrame& frame : dataset.frames) {
    true_position[frame.image_name] = frame.origin_from_cam.translation;
  }
  std::vector<Eigen::Vector3d> estimated, expected;
  for (const MetricSubModel& metric : run.calibration.metric_models) {
    for (const auto& [id, image] : metric.model.images) {
      const auto it = true_position.find(image.name);
      if (it == true_position.end()) continue;
      estimated.push_back(Inverse(image.cam_from_world).translation);
      expected.push_back(it->second);
    }
  }
  std::printf(
      "       metric model scale %+8.4f %% (over %zu registered images)\n",
      100.0 * (RelativeModelScale(estimated, expected) - 1.0),
      estimated.size());
  std::cout << "       report: "
            << (fs::path(settings.workspace_path) / "report.html").string()
            << "\n";
  return ExitCodeFor(result);
}

}  // namespace

int RunDemo(int argc, char** argv) {
  CLI::App app{
      "Renders a synthetic scene with a known camera mount, reconstructs it "
      "with COLMAP, calibrates and compares with the ground truth.",
      "odomcal demo"};
  std::string workspace = "odomcal_demo";
  std::string preset = "default";
  uint64_t seed = 1;
  bool simulated = false;
  DriveSimulatorOptions simulation;
  simulation.duration_s = 120.0;
  // Realistic wheel odometry and SfM errors for --simulated.
  simulation.wheel_scale_error_left = 0.003;
  simulation.wheel_scale_error_right = -0.002;
  simulation.yaw_rate_bias_radps = 0.002;
  simulation.camera_rotation_noise_deg = 0.02;
  simulation.camera_position_noise = 0.002;
  app.add_option("--workspace_path",
                 workspace,
                 "folder for the demo's inputs and outputs (its files are "
                 "replaced on every run; finished COLMAP stages are reused)")
      ->capture_default_str();
  app.add_option("--preset",
                 preset,
                 "rendered scene preset (see odomcal render --help)")
      ->capture_default_str();
  app.add_option("--seed", seed, "scene / simulation seed")
      ->check(AtLeast(0))
      ->capture_default_str();
  app.add_flag("--simulated",
               simulated,
               "calibrate a simulated trajectory pair instead (no images, no "
               "COLMAP; about a second)");
  app.add_option(
         "--duration_s", simulation.duration_s, "--simulated: drive duration")
      ->check(InRange(5, 3600))
      ->capture_default_str();
  app.add_option("--ground_tilt_deg",
                 simulation.ground_tilt_deg,
                 "--simulated: slope of a rolling ground, degrees along each "
                 "of two axes (the camera moves in 3-D, the wheel odometry "
                 "stays planar)")
      ->check(InRange(0, 30))
      ->capture_default_str();
  // The simulated drive's systematic errors (true over nominal), for
  // measuring their estimation (docs/systematics.md).
  std::optional<double> wheel_left, wheel_right;
  app.add_option("--sim_wheel_radius_left",
                 wheel_left,
                 "--simulated: true left wheel radius over nominal (default "
                 "1 / 1.003)");
  app.add_option("--sim_wheel_radius_right",
                 wheel_right,
                 "--simulated: true right wheel radius over nominal (default "
                 "1 / 0.998)");
  app.add_option("--sim_wheel_track",
                 simulation.wheel_track_error,
                 "--simulated: true wheel track over nominal, minus 1")
      ->capture_default_str();
  app.add_option("--sim_yaw_rate_bias_radps",
                 simulation.yaw_rate_bias_radps,
                 "--simulated: heading drift added by the odometry")
      ->capture_default_str();
  app.add_option("--sim_camera_time_offset_s",
                 simulation.camera_time_offset_s,
                 "--simulated: true clock offset (odometry_time = camera_time "
                 "+ offset)")
      ->capture_default_str();
  app.add_option("--sim_camera_rate_hz",
                 simulation.camera_rate_hz,
                 "--simulated: camera rate (must divide the 50 Hz odometry)")
      ->capture_default_str();
  std::string profile = "manoeuvres";
  app.add_option("--sim_profile",
                 profile,
                 "--simulated: manoeuvres (constant speed and yaw rate, "
                 "switched abruptly) or smooth (speed and yaw rate sums of "
                 "slow sinusoids, as robots drive)")
      ->check(CLI::IsMember({"manoeuvres", "smooth"}))
      ->capture_default_str();
  bool wheel_travels = false;
  app.add_flag("--sim_wheel_travels",
               wheel_travels,
               "--simulated: write the odometry as wheel travels (wheels.csv, "
               "timestamp,left_m,right_m; no yaw-rate bias) and calibrate "
               "from them (needs --wheel_track_m)");
  CalibrateInputs inputs;
  AddCalibrationFlags(&app, &inputs);
  if (const auto exit_code = ParseFlags(&app, argc, argv)) {
    return *exit_code;
  }
  return RunReportingErrors(app, [&]() -> int {
    if (simulated) {
      simulation.seed = seed;
      simulation.profile = profile == "smooth" ? DriveProfile::kSmooth
                                               : DriveProfile::kManoeuvres;
      if (wheel_left)
        simulation.wheel_scale_error_left = 1.0 / *wheel_left - 1.0;
      if (wheel_right) {
        simulation.wheel_scale_error_right = 1.0 / *wheel_right - 1.0;
      }
      return RunSimulatedDemo(workspace, simulation, wheel_travels, inputs);
    }
    return RunRenderedDemo(workspace, preset, seed, inputs);
  });
}

}  // namespace odomcal
