// [4] mapper runs of the reconstruction pipeline (reconstruction_stages.h):
// arguments, output folders, extra runs beside the main model, and a run
// with one random seed checked against the odometry.
#include "odomcal/plugin/colmap/joint_adjustment_run.h"
#include "odomcal/plugin/colmap/reconstruction_stages.h"
#include "odomcal/plugin/output/output_folder.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace odomcal::reconstruction {

namespace fs = std::filesystem;

namespace {

// StartMapper, waited for (COLMAP's lines to the runner's listener).
ColmapStageResult RunMapper(ColmapRunner* colmap,
                            const ReconstructionOptions& run,
                            const std::string& entry,
                            const MapperCommand& command) {
  RunningStage stage =
      StartMapper(colmap, run, entry, command.arguments, command.program);
  stage.WaitForEnd(colmap->options().on_output_line);
  return stage.Finish();
}

// Whether a mapper run into `output` produced a model.
bool HasModel(const fs::path& output) { return fs::exists(output / "0"); }

// "the odometry agrees with all 34 motion pairs", "no motion pair
// contradicts the odometry (2 of 34 not used, within RANSAC's gate)", "2 of
// 34 motion pairs contradict the odometry", "none of 34 motion pairs could
// be tested" (too little motion), with the calibration status when it gave
// no answer.
std::string OdometryVerdict(const MapperAttempt& attempt) {
  std::string verdict;
  if (!attempt.pairs_tested) {
    verdict = "none of " + std::to_string(attempt.num_pairs) +
              " motion pairs could be tested against the odometry";
  } else if (attempt.num_contradicting_pairs == 0 &&
             attempt.num_pairs_used == attempt.num_pairs) {
    verdict = "the odometry agrees with all " +
              std::to_string(attempt.num_pairs) + " motion pairs";
  } else if (attempt.num_contradicting_pairs == 0) {
    verdict = "no motion pair contradicts the odometry (" +
              std::to_string(attempt.num_pairs - attempt.num_pairs_used) +
              " of " + std::to_string(attempt.num_pairs) +
              " not used, within RANSAC's gate)";
  } else {
    verdict = std::to_string(attempt.num_contradicting_pairs) + " of " +
              std::to_string(attempt.num_pairs) +
              " motion pairs contradict the odometry";
  }
  if (attempt.status != CalibrationStatus::kSuccess) {
    verdict += " (calibration: " + ToString(attempt.status) + ")";
  }
  return verdict;
}

}  // namespace

ColmapCalibrationInputs CheckCalibrationInputs(const ReconstructionOptions& run,
                                               const std::string& model_path,
                                               const std::string& database) {
  ColmapCalibrationInputs inputs = run.project;
  inputs.model_path = model_path;
  inputs.database_path = database;
  inputs.joint_adjustment.use = JointAdjustmentUse::kOff;
  return inputs;
}

// Where `colmap mapper` run as stage "mapper_<entry>" writes its
// sub-models: mapper_attempts/<entry> in the workspace.
fs::path MapperOutput(const ReconstructionOptions& run,
                      const std::string& entry) {
  return fs::path(run.workspace_path) / "mapper_attempts" / entry;
}

// `colmap mapper` on `database`'s matches of the images in `image_list`,
// with the intrinsics kept fixed when given (--camera_params), and the
// random seed when `random_seed` holds one, in the option names of
// `version`.
std::vector<std::string> MapperArguments(const ReconstructionOptions& run,
                                         const ColmapVersion& version,
                                         const std::string& database,
                                         const fs::path& output,
                                         const fs::path& image_list,
                                         std::optional<int> random_seed,
                                         int num_threads) {
  const bool fixed_intrinsics = !run.camera_params.empty();
  const ColmapOptionNames names = ColmapOptionNamesFor(version);
  std::vector<std::string> arguments = {"mapper",
                                        "--database_path",
                                        database,
                                        "--image_path",
                                        run.image_path,
                                        "--output_path",
                                        output.string(),
                                        "--" + names.mapper_image_list_path,
                                        image_list.string()};
  if (random_seed) {
    for (const std::string& name : names.mapper_random_seed) {
      arguments.insert(arguments.end(),
                       {"--" + name, std::to_string(*random_seed)});
    }
  }
  arguments.insert(arguments.end(),
                   {"--Mapper.num_threads",
                    std::to_string(num_threads),
                    "--Mapper.ba_refine_focal_length",
                    fixed_intrinsics ? "0" : "1",
                    "--Mapper.ba_refine_principal_point",
                    "0",
                    "--Mapper.ba_refine_extra_params",
                    fixed_intrinsics ? "0" : "1"});
  return arguments;
}

bool GlobalMapperIsGlomap(const ColmapVersion& version) {
  return !version.AtLeast(4, 0);
}

MapperCommand GlobalMapperCommand(const ReconstructionOptions& run,
                                  const ColmapVersion& version,
                                  const std::string& database,
                                  const fs::path& output,
                                  const fs::path& image_list,
                                  std::optional<int> random_seed,
                                  int num_threads) {
  const bool fixed_intrinsics = !run.camera_params.empty();
  MapperCommand command;
  if (GlobalMapperIsGlomap(version)) {
    // GLOMAP 1.x (glomap/exe/global_mapper.cc, controllers/option_manager.cc):
    // no image list, seed or thread options.
    command.program = ColmapProgram::kGlomap;
    command.arguments = {"mapper",
                         "--database_path",
                         database,
                         "--image_path",
                         run.image_path,
                         "--output_path",
                         output.string(),
                         "--BundleAdjustment.optimize_intrinsics",
                         fixed_intrinsics ? "0" : "1",
                         "--BundleAdjustment.optimize_principal_point",
                         "0"};
    return command;
  }
  // COLMAP 4.0-4.1 RunGlobalMapper (exe/sfm.cc) and AddGlobalMapperOptions.
  command.arguments = {"global_mapper",
                       "--database_path",
                       database,
                       "--image_path",
                       run.image_path,
                       "--output_path",
                       output.string(),
                       "--GlobalMapper.image_list_path",
                       image_list.string(),
                       "--GlobalMapper.num_threads",
                       std::to_string(num_threads)};
  if (random_seed) {
    command.arguments.insert(
        command.arguments.end(),
        {"--GlobalMapper.random_seed", std::to_string(*random_seed)});
  }
  command.arguments.insert(command.arguments.end(),
                           {"--GlobalMapper.ba_refine_focal_length",
                            fixed_intrinsics ? "0" : "1",
                            "--GlobalMapper.ba_refine_principal_point",
                            "0",
                            "--GlobalMapper.ba_refine_extra_params",
                            fixed_intrinsics ? "0" : "1"});
  return command;
}

// Starts `arguments` (MapperArguments into MapperOutput(run, entry)) as
// stage "mapper_<entry>". Unless the stage is reused, its output folder is
// emptied first: a rerun must not mix new sub-models with stale ones.
RunningStage StartMapper(ColmapRunner* colmap,
                         const ReconstructionOptions& run,
                         const std::string& entry,
                         const std::vector<std::string>& arguments,
                         ColmapProgram program) {
  const std::string stage = "mapper_" + entry;
  const fs::path output = MapperOutput(run, entry);
  const std::vector<std::string> outputs = {(output / "0").string()};
  if (!colmap->WillReuse(stage, arguments, outputs, program)) {
    RemoveOwnedOutput(run.workspace_path, "mapper_attempts/" + entry);
  }
  std::error_code error;
  fs::create_directories(output, error);
  return colmap->StartStage(stage, arguments, outputs, program);
}

// The end of a mapper run for a model beside the main one (a stretch, a
// chunk): it is extra, so COLMAP failing on it (e.g. a CHECK on images
// without features) or giving no model ends `clock`'s stage with "no
// model..." and returns nothing, and the run goes on without it.
std::optional<ColmapStageResult> FinishExtraMapper(
    RunningStage* stage,
    const ReconstructionOptions& run,
    const std::string& entry,
    StageClock* clock) {
  ColmapStageResult result;
  try {
    result = stage->Finish();
  } catch (const ColmapError& failure) {
    clock->Done(std::string("no model: ") + failure.what(), stage->seconds());
    return std::nullopt;
  }
  if (!HasModel(MapperOutput(run, entry))) {
    clock->Done("no model, log " + result.log_path, stage->seconds());
    return std::nullopt;
  }
  return result;
}

// An extra mapper run (FinishExtraMapper), started and waited for.
std::optional<ColmapStageResult> RunExtraMapper(
    ColmapRunner* colmap,
    const ReconstructionOptions& run,
    const std::string& entry,
    const std::vector<std::string>& arguments,
    StageClock* clock) {
  RunningStage stage = StartMapper(colmap, run, entry, arguments);
  stage.WaitForEnd(colmap->options().on_output_line);
  return FinishExtraMapper(&stage, run, entry, clock);
}

// [4]: `colmap mapper` with `seed` on the round's matches, its model
// calibrated and recorded in `policy`.
void MapWithSeed(ColmapRunner* colmap,
                 const ReconstructionOptions& run,
                 const MatchingRound& round,
                 const std::vector<TimedImage>& images,
                 const Trajectory& odometry,
                 int seed,
                 Progress* progress,
                 MapperStart* start,
                 MapperPolicy* policy) {
  const fs::path workspace(run.workspace_path);
  const std::string prefix = round.index == 0 ? "" : "rematch_";
  MapperAttempt attempt;
  attempt.matching_round = round.index;
  attempt.random_seed = seed;
  const bool global = run.mapper_kind == MapperKind::kGlobal;
  const bool glomap = global && GlobalMapperIsGlomap(colmap->Version());
  const std::string entry = prefix + "seed_" + std::to_string(seed);
  const fs::path output = MapperOutput(run, entry);
  const fs::path image_list = workspace / "image_list.txt";
  MapperCommand command;
  if (global) {
    command = GlobalMapperCommand(run,
                                  colmap->Version(),
                                  round.database,
                                  output,
                                  image_list,
                                  seed,
                                  run.num_threads);
  } else {
    command.arguments = MapperArguments(run,
                                        colmap->Version(),
                                        round.database,
                                        output,
                                        image_list,
                                        seed,
                                        run.num_threads);
    if (start->initialization) {
      const std::vector<std::string> initialization =
          start->initialization->MapperArguments();
      command.arguments.insert(command.arguments.end(),
                               initialization.begin(),
                               initialization.end());
      attempt.initialization = ToString(start->initialization->kind);
      if (start->initialization->pair) {
        attempt.initial_pair = {start->initialization->pair->name1,
                                start->initialization->pair->name2};
      }
    }
  }
  const std::string what = glomap   ? "GLOMAP global mapping"
                           : global ? "COLMAP global mapping"
                                    : "COLMAP mapping";
  StageClock clock(
      progress,
      4,
      what + (round.index == 0 ? "" : " the new matches") +
          (glomap ? "" : ", --random_seed " + std::to_string(seed)));
  const ColmapStageResult stage = RunMapper(colmap, run, entry, command);
  attempt.model_path = output.string();
  fs::path model = output;
  // The ladder is for a drive without any model yet, once.
  if (!HasModel(output) && !global && !start->climbed && policy->Best() < 0) {
    clock.Done("no model, log " + stage.log_path);
    start->climbed = true;
    LadderImages ladder;
    ladder.mapped = images;
    ladder.image_list = image_list;
    ladder.what = "the drive";
    const InitializationClimb climb = ClimbInitializationLadder(colmap,
                                                                run,
                                                                round,
                                                                odometry,
                                                                ladder,
                                                                entry,
                                                                seed,
                                                                -1,
                                                                run.num_threads,
                                                                progress);
    start->summary = DescribeClimb(climb);
    if (climb.output.empty()) {
      // This run's record (the policy's) and the rungs'.
      start->attempts = climb.rungs;
      attempt.failure_cause = climb.first.failure_cause;
      policy->Record(attempt);
      return;
    }
    // This run's record is the rung's model, calibrated below; the run
    // that gave none and the rungs before are recorded beside it.
    start->attempts = {climb.first};
    start->attempts.insert(
        start->attempts.end(), climb.rungs.begin(), climb.rungs.end() - 1);
    start->initialization = climb.used;
    model = climb.output;
    attempt.initialization = ToString(climb.used->kind);
    if (climb.used->pair) {
      attempt.initial_pair = {climb.used->pair->name1, climb.used->pair->name2};
    }
  } else if (!HasModel(output)) {
    attempt.failure_cause = MapperFailureCause(stage.log_path);
    policy->Record(attempt);
    clock.Done("no model, log " + stage.log_path);
    return;
  }
  const ColmapCalibrationRun calibration = CalibrateColmapProject(
      CheckCalibrationInputs(run, model.string(), round.database));
  const MapperAttempt started = attempt;
  attempt = SummarizeMapperAttempt(
      seed, model.string(), calibration.segments, calibration.check);
  attempt.initialization = started.initialization;
  attempt.initial_pair = started.initial_pair;
  attempt.matching_round = round.index;
  policy->Record(attempt);
  const bool climbed = model != output;
  std::string note = (climbed ? "    its model: " : Note(stage) + "; ") +
                     OdometryVerdict(attempt);
  if (policy->repeated()) {
    note += ", the same as with " + MapperAttemptName(*policy->repeated());
  } else if (policy->Next().kind == MapperStep::Kind::kMap) {
    note += ": mapping again";
  }
  if (climbed) {
    progress->Note(4, note);  // the first run's clock said "no model"
  } else {
    clock.Done(note);
  }
}

// `workspace`/`entry` becomes a copy of folder `source`; a failure leaves no
// half copy under that name.
void ReplaceWithCopy(const fs::path& source,
                     const std::string& workspace,
                     const std::string& entry) {
  const fs::path temporary = fs::path(workspace) / (entry + ".tmp");
  RemoveOwnedOutput(workspace, entry + ".tmp");
  fs::copy(source, temporary, fs::copy_options::recursive);
  RemoveOwnedOutput(workspace, entry);
  fs::rename(temporary, fs::path(workspace) / entry);
}

// The number a sub-model folder is named by ("0", "1", ...); -1 for any
// other name.
int SubModelNumber(const std::string& name) {
  const bool numbered =
      !name.empty() && name.size() < 9 &&
      std::all_of(name.begin(), name.end(), [](unsigned char c) {
        return std::isdigit(c);
      });
  return numbered ? std::stoi(name) : -1;
}

// "images 86-300".
std::string ImageRange(int first, int last) {
  return "images " + std::to_string(first + 1) + "-" + std::to_string(last + 1);
}

}  // namespace odomcal::reconstruction
