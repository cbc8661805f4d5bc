#include "odomcal/plugin/cli/colmap_command.h"

#include "odomcal/adapters/colmap_cameras.h"
#include "odomcal/adapters/format_error.h"
#include "odomcal/plugin/cli/calibrate_command.h"
#include "odomcal/plugin/cli/colmap_rig_outputs.h"
#include "odomcal/plugin/cli/command_flags.h"
#include "odomcal/plugin/cli/rig_report.h"
#include "odomcal/plugin/colmap/colmap_calibration.h"
#include "odomcal/plugin/output/output_file.h"
#include "odomcal/plugin/report/colmap_calibration_outputs.h"
#include "odomcal/plugin/report/colmap_report.h"
#include "odomcal/plugin/report/joint_adjustment_report.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <filesystem>
#include <iostream>
#include <stdexcept>

namespace odomcal {
namespace {

int RunColmapRig(const ColmapCalibrationInputs& inputs,
                 const ColmapProjectCameras& cameras,
                 int reference,
                 const std::string& output_path,
                 bool quiet,
                 const CalibrationProgress& progress) {
  if (!quiet) {
    std::cout << "cameras: " << cameras.cameras.size() << " ("
              << ColmapCameraGroupingText(cameras.grouping) << "):";
    for (const ColmapProjectCamera& camera : cameras.cameras) {
      std::cout << " " << camera.name << " (" << camera.num_images
                << " images)";
    }
    std::cout << "\n" << std::flush;
  }
  const ColmapRigRun rig =
      CalibrateColmapRig(inputs, cameras, reference, progress);
  nlohmann::json echo = ProjectFlagsEcho(inputs);
  echo["inputs"]["reference_camera"] = cameras.cameras[reference].name;
  const RigCalibrationRun as_rig =
      RigCalibrationOf(rig, "odomcal colmap", echo);
  const std::vector<std::string> written =
      WriteColmapRigOutputs(rig, as_rig, output_path, true);
  if (!quiet) {
    std::cout << RigCalibrationSummary(as_rig);
    std::string names;
    for (const std::string& name : written)
      names += (names.empty() ? "" : ", ") + name;
    std::cout << "  wrote " << output_path << "/{" << names << "}\n";
  }
  if (as_rig.NumCalibrated() > 0) {
    std::cout << std::flush;
    for (const std::string& warning : as_rig.Warnings()) {
      std::cerr << "odomcal colmap: warning: " << warning << "\n";
    }
  }
  return RigExitCode(as_rig);
}

}  // namespace

int RunColmap(int argc, char** argv) {
  CLI::App app{
      "Calibrates the camera-to-odometry extrinsic and the metric scale of an "
      "existing COLMAP project, and exports the model in metres in the "
      "odometry frame.",
      "odomcal colmap"};
  ColmapCalibrationInputs inputs;
  ProjectFlags flags;
  std::string output_path;
  bool overwrite = false;
  bool quiet = false;
  AddFlags(ColmapModelFlags(), &app, &inputs);
  app.add_option("--output_path",
                 output_path,
                 "output folder (created; must not be inside the project)")
      ->required();
  app.add_flag(
      "--overwrite", overwrite, "replace odomcal's files in --output_path");
  app.add_flag("--quiet", quiet, "print only errors");
  std::string reference_camera;
  app.add_option("--reference_camera",
                 reference_camera,
                 "a project with several cameras: the camera whose result is "
                 "the top level of calibration.json (default: the first)");
  AddProjectFlags(&app, &inputs, &flags);
  if (const auto exit_code = ParseFlags(&app, argc, argv)) {
    return *exit_code;
  }
  return RunReportingErrors(app, [&]() -> int {
    FinishProjectFlags(flags, &inputs);
    const std::string database_folder =
        std::filesystem::path(inputs.database_path).parent_path().string();
    PrepareOutputFolder({output_path, "--output_path"},
                        {{inputs.model_path, "--model_path"},
                         {inputs.database_path, "--database_path"},
                         {database_folder, "the folder of --database_path"},
                         {inputs.odometry_path, "--odometry"},
                         {inputs.image_timestamps_path, "--image_timestamps"}},
                        ColmapCalibrationOutputEntries(),
                        overwrite ? ExistingOutputs::kReplaceOwn
                                  : ExistingOutputs::kRefuseNonEmptyFolder);
    // A long step (the joint adjustment) says where it is every 10 s.
    const auto start = std::chrono::steady_clock::now();
    auto last_line = start;
    const CalibrationProgress progress = [&](const std::string& message) {
      const auto now = std::chrono::steady_clock::now();
      if (quiet || now - last_line < std::chrono::seconds(10)) return;
      last_line = now;
      std::cout << "  " << message << "\n" << std::flush;
    };
    inputs.Check();  // before the model is read, as the calibration does
    const ColmapProjectCameras cameras =
        FindColmapProjectCameras(inputs.model_path);
    if (cameras.IsRig()) {
      return RunColmapRig(inputs,
                          cameras,
                          ColmapReferenceCamera(cameras, reference_camera),
                          output_path,
                          quiet,
                          progress);
    }
    if (!reference_camera.empty()) {
      throw std::invalid_argument(
          "--reference_camera: the project has one camera (" +
          std::string(ColmapCameraGroupingText(cameras.grouping)) +
          "); the option is for a project with several");
    }
    const ColmapCalibrationRun run = CalibrateColmapProject(inputs, progress);
    const ReportContext context = ProjectReportContext(
        inputs, run, "odomcal colmap", ProjectFlagsEcho(inputs));
    const std::vector<std::string> written =
        WriteColmapCalibrationOutputs(run, context, output_path);
    if (!quiet) {
      std::cout << CalibrationSummary(run.check.result, context)
                << JointAdjustmentSummary(run);
      std::string names;
      for (const std::string& name : written)
        names += (names.empty() ? "" : ", ") + name;
      std::cout << "  wrote " << output_path << "/{" << names << "}\n";
    }
    return ExitCodeFor(run.check.result);
  });
}

}  // namespace odomcal
