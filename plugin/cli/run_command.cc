// `odomcal run`: the flags become ReconstructionOptions, the pipeline
// (reconstruction_pipeline.h) runs with its progress printed, and the
// outputs of `odomcal colmap` are written in the workspace.

#include "odomcal/plugin/cli/run_command.h"

#include "odomcal/plugin/cli/bag_commands.h"
#include "odomcal/plugin/cli/calibrate_command.h"
#include "odomcal/plugin/cli/command_flags.h"
#include "odomcal/plugin/cli/rig_run.h"
#include "odomcal/plugin/options/bag_flags.h"
#include "odomcal/plugin/output/output_file.h"
#include "odomcal/plugin/output/output_folder.h"
#include "odomcal/plugin/report/colmap_calibration_outputs.h"
#include "odomcal/plugin/report/colmap_report.h"
#include "odomcal/plugin/report/joint_adjustment_report.h"

#include <unistd.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <utility>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

// Prints the pipeline's progress: "[2/5] COLMAP feature extraction ... done,
// log <path> (3.2 s)", and the notes between stages on lines of their own.
// While COLMAP runs, what it reports: on a terminal in place after the
// stage's title (\r), otherwise (a log) as indented lines every 10 s.
// The last stage's line is ended by Finish, once the outputs are written.
class ProgressPrinter {
 public:
  ProgressPrinter() : terminal_(::isatty(STDOUT_FILENO) == 1) {}
  ProgressPrinter(const ProgressPrinter&) = delete;
  ProgressPrinter& operator=(const ProgressPrinter&) = delete;
  // An exception between a stage's title and its end still ends the line.
  ~ProgressPrinter() {
    if (open_) std::cout << std::endl;
  }

  void Print(const PipelineProgress& progress) {
    switch (progress.event) {
      case PipelineProgress::Event::kStageStarted:
        title_ = "[" + std::to_string(progress.stage) + "/" +
                 std::to_string(progress.num_stages) + "] " + progress.message;
        std::cout << title_ << std::flush;
        open_ = true;
        live_shown_ = false;
        start_ = std::chrono::steady_clock::now();
        last_line_ = start_;
        break;
      case PipelineProgress::Event::kStageProgress:
        Live(progress.message);
        break;
      case PipelineProgress::Event::kStageFinished:
        if (progress.stage < progress.num_stages) {
          Finish(progress.message, progress.seconds);
        }
        break;
      case PipelineProgress::Event::kNote:
        std::cout << progress.message << "\n" << std::flush;
        break;
    }
  }

  // `seconds`: the stage's own time (a chunk mapped beside others); by
  // default the time since its title.
  void Finish(const std::string& note, std::optional<double> seconds = {}) {
    open_ = false;
    char took[32];
    std::snprintf(
        took,
        sizeof(took),
        "%.1f s",
        seconds.value_or(std::chrono::duration<double>(
                             std::chrono::steady_clock::now() - start_)
                             .count()));
    if (live_shown_ && terminal_) {
      std::cout << "\r" << title_ << kClearToEndOfLine;
    } else if (live_shown_) {
      std::cout << "   ";
    }
    std::cout << " ... " << note << " (" << took << ")\n" << std::flush;
  }

 private:
  static constexpr const char* kClearToEndOfLine = "\033[K";

  void Live(const std::string& message) {
    if (!open_) return;
    if (terminal_) {
      std::cout << "\r" << title_ << ": " << message << kClearToEndOfLine
                << std::flush;
      live_shown_ = true;
      return;
    }
    const auto now = std::chrono::steady_clock::now();
    if (now - last_line_ < std::chrono::seconds(10)) return;
    last_line_ = now;
    if (!live_shown_) std::cout << "\n";
    std::cout << "    " << message << "\n" << std::flush;
    live_shown_ = true;
  }

  bool terminal_ = false;
  bool open_ = false;
  bool live_shown_ = false;
  std::string title_;
  std::chrono::steady_clock::time_point start_, last_line_;
};

}  // namespace

std::string JoinNames(const std::vector<std::string>& names) {
  std::string joined;
  for (const std::string& name : names)
    joined += (joined.empty() ? "" : ", ") + name;
  return joined;
}

RunOutcome RunAndWriteOutputs(const ReconstructionOptions& options,
                              const std::string& command,
                              const nlohmann::json& bag_echo) {
  // Reruns reuse the workspace: odomcal's own entries in it are replaced.
  std::vector<std::string> entries = ColmapCalibrationOutputEntries();
  const std::vector<std::string> pipeline = ReconstructionWorkspaceEntries();
  entries.insert(entries.end(), pipeline.begin(), pipeline.end());
  PrepareOutputFolder({options.workspace_path, "--workspace_path"},
                      UserInputs(options),
                      entries,
                      ExistingOutputs::kReplaceOwn);
  ProgressPrinter printer;
  const ReconstructionResult result = ReconstructAndCalibrate(
      options, [&printer](const PipelineProgress& progress) {
        printer.Print(progress);
      });
  RunOutcome outcome;
  outcome.calibration = result.calibration;
  // The model and database the pipeline made (null when it refused the
  // drive before COLMAP).
  ColmapCalibrationInputs calibrated = options.project;
  calibrated.model_path = result.model_path;
  calibrated.database_path = result.database_path;
  nlohmann::json echo = RunResultFlagsEcho(options, result);
  if (!bag_echo.is_null()) MergeFlagEcho(bag_echo, &echo);
  outcome.context =
      ProjectReportContext(calibrated, outcome.calibration, command, echo);
  const fs::path workspace(options.workspace_path);
  if (result.refused_before_colmap) {
    // calibration.json with the status only, and no other output of an
    // earlier run left beside it to be mistaken for this one's.
    for (const std::string& entry : ColmapCalibrationOutputEntries()) {
      if (entry != "calibration.json") {
        RemoveOwnedOutput(options.workspace_path, entry);
      }
    }
    WriteFileAtomically(
        (workspace / "calibration.json").string(),
        ColmapCalibrationToJson(outcome.calibration, outcome.context).dump(2) +
            "\n");
    outcome.written_outputs = {"calibration.json"};
    std::cout << "wrote " << (workspace / "calibration.json").string()
              << " (the status only)\n";
    return outcome;
  }
  outcome.written_outputs = WriteColmapCalibrationOutputs(
      outcome.calibration, outcome.context, options.workspace_path);
  outcome.written_outputs.insert(outcome.written_outputs.begin() + 2,
                                 "sparse/");
  printer.Finish("wrote " + JoinNames(outcome.written_outputs));
  return outcome;
}

int RunRun(int argc, char** argv) {
  CLI::App app{
      "Reconstructs an image folder with COLMAP (odometry-guided) and "
      "calibrates the camera-to-odometry extrinsic and metric scale.",
      "odomcal run"};
  ReconstructionOptions run;
  ProjectFlags flags;
  AddRunFlags(&app, &run);
  AddProjectFlags(&app, &run.project, &flags);
  // --bag instead of --image_path, --odometry and --image_timestamps.
  std::string bag_path;
  bag::BagExtractionOptions bag_options;
  app.add_option("--bag",
                 bag_path,
                 "a robot bag (ROS 1, or ROS 2: folder with metadata.yaml, "
                 ".db3 or .mcap) instead of --image_path, --odometry and "
                 "--image_timestamps: extracted into WS/bag_inputs, its "
                 "CameraInfo as --camera_params")
      ->check(CLI::ExistingPath);
  AddFlags(BagTopicFlags(), &app, &bag_options);
  for (const char* flag : {"--image_path", "--odometry"}) {
    app.get_option(flag)->required(false);
  }
  bool rig = false;
  app.add_flag("--rig",
               rig,
               "each sub-folder of --image_path is one camera, named by it "
               "(images/front/..., images/rear/...); with --bag, each image "
               "topic: every camera calibrated against the one odometry "
               "(docs/cli.md, \"Several cameras\")");
  std::string reference_camera;
  app.add_option("--reference_camera",
                 reference_camera,
                 "with --rig (or several --image_topic): the camera whose "
                 "result is the top level of calibration.json (default: the "
                 "first)");
  // With --rig, one NAME=PARAMS per camera (or one PARAMS for all).
  std::vector<std::string> camera_params;
  app.get_option("--camera_params")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->each([&camera_params](const std::string& value) {
        camera_params.push_back(value);
      });
  if (const auto exit_code = ParseFlags(&app, argc, argv)) {
    return *exit_code;
  }
  const bool from_bag = !bag_path.empty();
  // Several image topics of a bag are a rig as --rig is.
  bag_options.rig = rig && from_bag;
  const bool several_cameras = rig || (from_bag && bag_options.IsRig());
  if (!several_cameras && camera_params.size() > 1) {
    std::cerr << "odomcal run: error: --camera_params is given "
              << camera_params.size()
              << " times: one camera takes one (several cameras: --rig)\n";
    return kExitBadInput;
  }
  if (!several_cameras && !reference_camera.empty()) {
    std::cerr << "odomcal run: error: --reference_camera requires --rig (or "
                 "several --image_topic with --bag)\n";
    return kExitBadInput;
  }
  for (const char* flag :
       {"--image_path", "--odometry", "--image_timestamps"}) {
    const bool given = app.count(flag) > 0;
    if (from_bag && given) {
      std::cerr << "odomcal run: error: --bag gives the images, their times "
                   "and the odometry: drop "
                << flag << "\n";
      return kExitBadInput;
    }
    if (!from_bag && !given && std::string(flag) != "--image_timestamps") {
      std::cerr << "odomcal run: error: " << flag
                << " is required (or --bag)\n";
      return kExitBadInput;
    }
  }

  return RunReportingErrors(app, [&]() -> int {
    FinishProjectFlags(flags, &run.project);
    nlohmann::json bag_echo = {
        {"inputs", {{"bag", nullptr}}},
        {"options", {{"bag", nlohmann::json::object()}}}};
    EchoOptions(BagTopicFlags(), bag_options, &bag_echo["options"]["bag"]);
    bag_echo["inputs"]["rig"] = several_cameras;
    if (from_bag) {
      bag_echo["inputs"]["bag"] = bag_path;
      std::cout << "odomcal run: extracting " << bag_path << "\n";
    }
    if (from_bag && several_cameras) {
      const BagRigCameras cameras =
          ExtractBagRigForRun(bag_path,
                              {camera_params, reference_camera},
                              &bag_options,
                              &run,
                              std::cout);
      return RunRigReconstruction(run,
                                  cameras.camera_params,
                                  reference_camera,
                                  bag_echo,
                                  cameras.camera_models);
    }
    if (from_bag) {
      ExtractBagForRun(bag_path,
                       app.count("--camera_params") > 0,
                       &bag_options,
                       &run,
                       std::cout);
    }
    if (rig) {
      return RunRigReconstruction(
          run, camera_params, reference_camera, bag_echo);
    }
    if (!camera_params.empty()) run.camera_params = camera_params.front();
    const RunOutcome outcome = RunAndWriteOutputs(run, "odomcal run", bag_echo);
    std::cout << CalibrationSummary(outcome.calibration.check.result,
                                    outcome.context)
              << JointAdjustmentSummary(outcome.calibration);
    if (!outcome.calibration.colmap_version.empty()) {
      const ColmapCalibrationRun& run = outcome.calibration;
      std::cout << "  reconstructed by: "
                << (run.colmap_mapper == "glomap mapper"
                        ? "GLOMAP (glomap mapper) on the features and matches "
                          "of COLMAP " +
                              run.colmap_version
                        : "COLMAP " + run.colmap_version + " (" +
                              run.colmap_mapper + ")")
                << "\n";
    }
    const auto& written = outcome.written_outputs;
    if (std::find(written.begin(), written.end(), "report.html") !=
        written.end()) {
      std::cout << "  report: "
                << (fs::path(run.workspace_path) / "report.html").string()
                << "\n";
    }
    return ExitCodeFor(outcome.calibration.check.result);
  });
}

}  // namespace odomcal
