#include "odomcal/plugin/cli/colmap_command.h"

#include "odomcal/adapters/format_error.h"
#include "odomcal/plugin/cli/calibrate_command.h"
#include "odomcal/plugin/cli/command_flags.h"
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
    const ColmapCalibrationRun run =
        CalibrateColmapProject(inputs, [&](const std::string& message) {
          const auto now = std::chrono::steady_clock::now();
          if (quiet || now - last_line < std::chrono::seconds(10)) return;
          last_line = now;
          std::cout << "  " << message << "\n" << std::flush;
        });
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
