// `odomcal run`: the flags become ReconstructionOptions, the pipeline
// (reconstruction_pipeline.h) runs with its progress printed, and the
// outputs of `odomcal colmap` are written in the workspace.

#include "odomcal/plugin/run_command.h"

#include "odomcal/plugin/calibrate_command.h"
#include "odomcal/plugin/colmap_calibration_outputs.h"
#include "odomcal/plugin/colmap_report.h"
#include "odomcal/plugin/output_file.h"
#include "odomcal/plugin/output_folder.h"
#include "odomcal/plugin/project_flags.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

// Prints the pipeline's progress: "[2/5] COLMAP feature extraction ... done,
// log <path> (3.2 s)", and the notes between stages on lines of their own.
// The last stage's line is ended by Finish, once the outputs are written.
class ProgressPrinter {
 public:
  ProgressPrinter() = default;
  ProgressPrinter(const ProgressPrinter&) = delete;
  ProgressPrinter& operator=(const ProgressPrinter&) = delete;
  // An exception between a stage's title and its end still ends the line.
  ~ProgressPrinter() {
    if (open_) std::cout << std::endl;
  }

  void Print(const PipelineProgress& progress) {
    switch (progress.event) {
      case PipelineProgress::Event::kStageStarted:
        std::cout << "[" << progress.stage << "/" << progress.num_stages << "] "
                  << progress.message << std::flush;
        open_ = true;
        start_ = std::chrono::steady_clock::now();
        break;
      case PipelineProgress::Event::kStageFinished:
        if (progress.stage < progress.num_stages) Finish(progress.message);
        break;
      case PipelineProgress::Event::kNote:
        std::cout << progress.message << "\n" << std::flush;
        break;
    }
  }

  void Finish(const std::string& note) {
    open_ = false;
    char seconds[32];
    std::snprintf(
        seconds,
        sizeof(seconds),
        "%.1f s",
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_)
            .count());
    std::cout << " ... " << note << " (" << seconds << ")\n" << std::flush;
  }

 private:
  bool open_ = false;
  std::chrono::steady_clock::time_point start_;
};

std::string JoinNames(const std::vector<std::string>& names) {
  std::string joined;
  for (const std::string& name : names)
    joined += (joined.empty() ? "" : ", ") + name;
  return joined;
}

}  // namespace

RunOutcome RunAndWriteOutputs(const ReconstructionOptions& options,
                              const std::string& command) {
  // Reruns reuse the workspace: odomcal's own entries in it are replaced.
  std::vector<std::string> entries = ColmapCalibrationOutputEntries();
  const std::vector<std::string> pipeline = ReconstructionWorkspaceEntries();
  entries.insert(entries.end(), pipeline.begin(), pipeline.end());
  PrepareOutputFolder(
      {options.workspace_path, "--workspace_path"},
      {{options.image_path, "--image_path"},
       {options.project.odometry_path, "--odometry"},
       {options.project.image_timestamps_path, "--image_timestamps"}},
      entries,
      ExistingOutputs::kReplaceOwn);
  ProgressPrinter printer;
  const ReconstructionResult result = ReconstructAndCalibrate(
      options, [&printer](const PipelineProgress& progress) {
        printer.Print(progress);
      });
  RunOutcome outcome;
  outcome.calibration = result.calibration;
  outcome.context =
      ProjectReportContext(options.project, outcome.calibration, command);
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
  app.add_option(
         "--image_path", run.image_path, "folder of images (sub-folders too)")
      ->required()
      ->check(CLI::ExistingDirectory);
  app.add_option("--workspace_path",
                 run.workspace_path,
                 "COLMAP workspace and outputs (created; reused on reruns)")
      ->required();
  app.add_option("--camera_model", run.camera_model, "COLMAP camera model")
      ->check(CLI::IsMember({"SIMPLE_PINHOLE",
                             "PINHOLE",
                             "SIMPLE_RADIAL",
                             "RADIAL",
                             "OPENCV",
                             "OPENCV_FISHEYE",
                             "FULL_OPENCV"}))
      ->capture_default_str();
  app.add_option("--camera_params",
                 run.camera_params,
                 "intrinsics in COLMAP's order, e.g. fx,fy,cx,cy; kept fixed "
                 "in the mapper (strongly recommended)");
  app.add_option("--matcher",
                 run.matcher,
                 "spatial: pairs by odometry position (COLMAP 3.8 priors); "
                 "sequential: by image name order")
      ->check(CLI::IsMember({"spatial", "sequential"}))
      ->capture_default_str();
  app.add_option("--spatial_neighbors",
                 run.spatial_neighbors,
                 "spatial matcher: neighbours per image")
      ->check(AtLeast(1))
      ->capture_default_str();
  app.add_option("--sequential_overlap",
                 run.sequential_overlap,
                 "sequential matcher: overlap")
      ->check(AtLeast(1))
      ->capture_default_str();
  app.add_option(
         "--max_num_features",
         run.max_num_features,
         "SIFT features per image (matching cost grows with its square)")
      ->check(AtLeast(1))
      ->capture_default_str();
  app.add_option("--num_threads", run.num_threads, "COLMAP threads")
      ->check(AtLeast(1))
      ->capture_default_str();
  app.add_option(
         "--frame_min_translation_m",
         run.frames.min_translation_m,
         "frame selection: keep an image once the robot moved this far...")
      ->check(AtLeast(0))
      ->capture_default_str();
  app.add_option("--frame_min_rotation_deg",
                 run.frames.min_rotation_deg,
                 "...or turned this much since the last kept image")
      ->check(AtLeast(0))
      ->capture_default_str();
  app.add_option(
         "--mapper_attempts",
         run.mapper.max_seeds,
         "COLMAP mapper runs (--random_seed 0, 1, ...) while the odometry "
         "contradicts motion pairs of the model; the model it contradicts "
         "least is kept; per matching")
      ->check(InRange(1, 20))
      ->capture_default_str();
  std::string rematch = "on";
  app.add_option("--rematch",
                 rematch,
                 "when the mapper's seeds do not give a model the odometry "
                 "accepts, match the images again and map the new matches too")
      ->check(CLI::IsMember({"on", "off"}))
      ->capture_default_str();
  app.add_option("--colmap_path", run.colmap_path, "the colmap executable")
      ->capture_default_str();
  app.add_flag("--force",
               run.force,
               "run COLMAP even when the odometry at the image times cannot "
               "determine the calibration (no or too few turns)");
  AddProjectFlags(&app, &run.project, &flags);
  if (const auto exit_code = ParseFlags(&app, argc, argv)) {
    return *exit_code;
  }

  return RunReportingErrors(app, [&]() -> int {
    FinishProjectFlags(flags, &run.project);
    run.mapper.max_matching_rounds = rematch == "on" ? 2 : 1;
    const RunOutcome outcome = RunAndWriteOutputs(run, "odomcal run");
    std::cout << CalibrationSummary(outcome.calibration.check.result,
                                    outcome.context);
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
