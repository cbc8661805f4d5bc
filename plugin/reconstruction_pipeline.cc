// Stages, each reported to the progress callback: [1] frame selection
// (odometry), then the excitation check (excitation_precheck.h; a drive the
// odometry cannot calibrate stops here, before COLMAP, unless `force`), [2]
// feature extraction, [3] position priors + matching, [4] mapping, repeated
// with other random seeds while the odometry contradicts the model (see
// mapper_policy.h), [5] calibration. COLMAP runs headless on the CPU;
// intrinsics are kept fixed in the mapper when given, because
// self-calibration on robot video drifts.

#include "odomcal/plugin/reconstruction_pipeline.h"

#include "odomcal/adapters/colmap_database.h"
#include "odomcal/adapters/colmap_database_priors.h"
#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/image_timestamps.h"
#include "odomcal/adapters/input_plausibility.h"
#include "odomcal/adapters/text_reader.h"
#include "odomcal/plugin/colmap_runner.h"
#include "odomcal/plugin/output_file.h"
#include "odomcal/plugin/output_folder.h"
#include "odomcal/plugin/output_guard.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

bool IsImageFile(const fs::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(),
                 extension.end(),
                 extension.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return extension == ".png" || extension == ".jpg" || extension == ".jpeg" ||
         extension == ".bmp" || extension == ".tif" || extension == ".tiff";
}

// Image names relative to the folder, '/'-separated, as COLMAP stores them.
std::vector<std::string> ListImages(const std::string& image_path) {
  std::vector<std::string> names;
  for (const auto& entry : fs::recursive_directory_iterator(image_path)) {
    if (entry.is_regular_file() && IsImageFile(entry.path())) {
      names.push_back(fs::relative(entry.path(), image_path).generic_string());
    }
  }
  std::sort(names.begin(), names.end());
  return names;
}

// Sends PipelineProgress to the caller's callback (if any), with a
// fraction that never decreases (stages 3 and 4 may run again).
class Progress {
 public:
  explicit Progress(const ProgressCallback& callback) : callback_(callback) {}

  void Send(PipelineProgress::Event event,
            int stage,
            const std::string& message,
            double seconds = 0.0) {
    PipelineProgress progress;
    progress.event = event;
    progress.stage = stage;
    progress.num_stages = kReconstructionStages;
    const int done =
        event == PipelineProgress::Event::kStageStarted ? stage - 1 : stage;
    fraction_ = std::max(
        fraction_,
        static_cast<double>(done) / static_cast<double>(kReconstructionStages));
    progress.fraction = fraction_;
    progress.message = message;
    progress.seconds = seconds;
    if (callback_) callback_(progress);
  }

  void Note(int stage, const std::string& message) {
    Send(PipelineProgress::Event::kNote, stage, message);
  }

 private:
  const ProgressCallback& callback_;
  double fraction_ = 0.0;
};

class StageClock {
 public:
  StageClock(Progress* progress, int index, const std::string& title)
      : progress_(progress), index_(index) {
    progress_->Send(PipelineProgress::Event::kStageStarted, index, title);
    start_ = std::chrono::steady_clock::now();
  }
  double Seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                         start_)
        .count();
  }
  void Done(const std::string& note) {
    progress_->Send(
        PipelineProgress::Event::kStageFinished, index_, note, Seconds());
  }

 private:
  Progress* progress_;
  int index_;
  std::chrono::steady_clock::time_point start_;
};

std::string Note(const ColmapStageResult& stage) {
  return stage.reused ? "reused from an earlier run"
                      : "done, log " + stage.log_path;
}

// The first line of `log_path` that holds `word`, or "".
std::string FirstLineWith(const std::string& log_path,
                          const std::string& word) {
  std::ifstream log(log_path);
  std::string line;
  while (std::getline(log, line)) {
    if (line.find(word) != std::string::npos) {
      return std::string(TrimBlanks(line));
    }
  }
  return "";
}

// COLMAP 3.8's feature_extractor skips files it cannot decode and still
// exits 0; the matchers then abort on an empty database with a stack trace.
// On failure the stage's marker is removed, so that a rerun extracts again.
void CheckImagesWereRead(const std::string& database,
                         size_t num_images,
                         const std::string& image_path,
                         const std::string& log_path,
                         const fs::path& stage_marker) {
  std::error_code ignored;
  if (!fs::exists(database)) {
    fs::remove(stage_marker, ignored);
    throw ColmapError("COLMAP feature_extractor wrote no database " + database +
                      " (see " + log_path + ")");
  }
  if (ReadColmapDatabaseImages(database).empty()) {
    fs::remove(stage_marker, ignored);
    const std::string error = FirstLineWith(log_path, "ERROR");
    throw ColmapError("COLMAP could read none of the " +
                      std::to_string(num_images) + " images in " + image_path +
                      " (see " + log_path +
                      (error.empty() ? "" : ": " + error) + ")");
  }
}

// "the odometry agrees with all 34 motion pairs", "2 of 34 motion pairs
// contradict the odometry", "none of 34 motion pairs could be tested" (too
// little motion), with the calibration status when it gave no answer.
std::string OdometryVerdict(const MapperAttempt& attempt) {
  std::string verdict;
  if (!attempt.pairs_tested) {
    verdict = "none of " + std::to_string(attempt.num_pairs) +
              " motion pairs could be tested against the odometry";
  } else if (attempt.num_contradicting_pairs == 0) {
    verdict = "the odometry agrees with all " +
              std::to_string(attempt.num_pairs) + " motion pairs";
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

// One matching of the images and the mapper runs on it.
struct MatchingRound {
  int index = 0;  // MapperAttempt::matching_round
  std::string database;
};

std::vector<std::string> MatcherArguments(const std::string& matcher,
                                          const MatchingRound& round,
                                          const ReconstructionOptions& run,
                                          const ColmapVersion& version) {
  const std::string matching = FeatureMatchingPrefix(version);
  std::vector<std::string> arguments = {matcher + "_matcher",
                                        "--database_path",
                                        round.database,
                                        "--" + matching + ".use_gpu",
                                        "0",
                                        "--" + matching + ".num_threads",
                                        std::to_string(run.num_threads)};
  if (matcher == "spatial") {
    arguments.insert(arguments.end(),
                     {"--SpatialMatching.is_gps",
                      "0",
                      "--SpatialMatching.ignore_z",
                      "1",
                      "--SpatialMatching.max_num_neighbors",
                      std::to_string(run.spatial_neighbors),
                      "--SpatialMatching.max_distance",
                      "5"});
  } else {
    arguments.insert(arguments.end(),
                     {"--SequentialMatching.overlap",
                      std::to_string(run.sequential_overlap)});
  }
  return arguments;
}

// [3] again: the features of `first_database` in round.database, matched
// anew with the same settings (COLMAP's two-view verification is random, so
// the matches differ). The copy is made (and every later stage runs anew)
// unless both stages finished on an earlier run with the same arguments.
void MatchAgain(ColmapRunner* colmap,
                const std::string& matcher,
                const MatchingRound& round,
                const std::string& first_database,
                const ReconstructionOptions& run,
                Progress* progress) {
  StageClock clock(
      progress,
      3,
      "COLMAP " + matcher + " matching again, into a copy of the features");
  const std::vector<std::string> cleaner = {"database_cleaner",
                                            "--type",
                                            "matches",
                                            "--database_path",
                                            round.database};
  const std::vector<std::string> matching =
      MatcherArguments(matcher, round, run, colmap->Version());
  const std::string cleaner_stage = "database_cleaner_rematch";
  const std::string matcher_stage = matcher + "_matcher_rematch";
  if (!colmap->WillReuse(cleaner_stage, cleaner, {round.database}) ||
      !colmap->WillReuse(matcher_stage, matching, {round.database})) {
    fs::copy_file(
        first_database, round.database, fs::copy_options::overwrite_existing);
    colmap->RunLaterStagesAnew();
  }
  colmap->RunStage(cleaner_stage, cleaner, {round.database});
  clock.Done(Note(colmap->RunStage(matcher_stage, matching, {round.database})) +
             ", database " + round.database);
}

// [4]: `colmap mapper` with `seed` on the round's matches, its model
// calibrated and recorded in `policy`.
void MapWithSeed(ColmapRunner* colmap,
                 const ReconstructionOptions& run,
                 const MatchingRound& round,
                 int seed,
                 Progress* progress,
                 MapperPolicy* policy) {
  const fs::path workspace(run.workspace_path);
  const std::string prefix = round.index == 0 ? "" : "rematch_";
  MapperAttempt attempt;
  attempt.matching_round = round.index;
  attempt.random_seed = seed;
  StageClock clock(progress,
                   4,
                   std::string("COLMAP mapping") +
                       (round.index == 0 ? "" : " the new matches") +
                       ", --random_seed " + std::to_string(seed));
  const std::string stage_name =
      "mapper_" + prefix + "seed_" + std::to_string(seed);
  const fs::path output =
      workspace / "mapper_attempts" / (prefix + "seed_" + std::to_string(seed));
  const bool fixed_intrinsics = !run.camera_params.empty();
  const std::vector<std::string> arguments = {
      "mapper",
      "--database_path",
      round.database,
      "--image_path",
      run.image_path,
      "--output_path",
      output.string(),
      "--image_list_path",
      (workspace / "image_list.txt").string(),
      "--random_seed",
      std::to_string(seed),
      "--Mapper.num_threads",
      std::to_string(run.num_threads),
      "--Mapper.ba_refine_focal_length",
      fixed_intrinsics ? "0" : "1",
      "--Mapper.ba_refine_principal_point",
      "0",
      "--Mapper.ba_refine_extra_params",
      fixed_intrinsics ? "0" : "1"};
  const std::vector<std::string> outputs = {(output / "0").string()};
  // A rerun must not mix new sub-models with stale ones.
  std::error_code error;
  if (!colmap->WillReuse(stage_name, arguments, outputs)) {
    RemoveOwnedOutput(
        run.workspace_path,
        "mapper_attempts/" + prefix + "seed_" + std::to_string(seed));
  }
  fs::create_directories(output, error);
  const ColmapStageResult stage =
      colmap->RunStage(stage_name, arguments, outputs);
  attempt.model_path = output.string();
  if (!fs::exists(output / "0")) {
    policy->Record(attempt);
    clock.Done("no model, log " + stage.log_path);
    return;
  }
  ColmapCalibrationInputs inputs = run.project;
  inputs.model_path = output.string();
  inputs.database_path = round.database;
  const ColmapCalibrationRun calibration = CalibrateColmapProject(inputs);
  attempt = SummarizeMapperAttempt(
      seed, output.string(), calibration.segments, calibration.check);
  attempt.matching_round = round.index;
  policy->Record(attempt);
  std::string note = Note(stage) + "; " + OdometryVerdict(attempt);
  if (policy->repeated()) {
    note += ", the same as with " + MapperAttemptName(*policy->repeated());
  } else if (policy->Next().kind == MapperStep::Kind::kMap) {
    note += ": mapping again";
  }
  clock.Done(note);
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

// "excitation (odometry at the 57 image times): 56 motion pairs, 0 left and
// 0 right turns above 2 deg: the calibration cannot be determined
// (unobservable); no COLMAP stage is run (--force runs them anyway)".
std::string ExcitationLine(const ExcitationPrecheck& precheck,
                           const CalibrationOptions& options,
                           bool force) {
  const CalibrationDiagnostics& d = precheck.verdict.diagnostics;
  std::ostringstream line;
  line << "excitation (odometry at the "
       << precheck.association.num_camera_poses
       << " image times): " << precheck.association.pairs.size()
       << " motion pairs, " << d.num_left_turns << " left and "
       << d.num_right_turns << " right turns above " << options.min_rotation_deg
       << " deg: ";
  if (precheck.determinable) {
    line << "enough to calibrate";
  } else {
    line << "the calibration cannot be determined ("
         << ToString(precheck.verdict.status) << "); "
         << (force ? "running COLMAP anyway (--force)"
                   : "no COLMAP stage is run (--force runs them anyway)");
  }
  return line.str();
}

}  // namespace

std::vector<std::string> ReconstructionWorkspaceEntries() {
  return {"image_list.txt",
          "database.db",
          "database_rematched.db",
          "logs",
          "stages",
          "commands.txt",
          "mapper_attempts",
          "sparse",
          "sparse.tmp"};
}

ReconstructionResult ReconstructAndCalibrate(const ReconstructionOptions& run,
                                             const ProgressCallback& callback) {
  const ColmapCalibrationInputs& inputs = run.project;
  MapperPolicy policy(run.mapper);  // checks its options first
  Progress progress(callback);
  const fs::path workspace(run.workspace_path);
  // Reruns reuse the workspace: odomcal's own entries in it are replaced.
  GuardedPaths guarded;
  guarded.inputs = {{run.image_path, "--image_path"},
                    {inputs.odometry_path, "--odometry"},
                    {inputs.image_timestamps_path, "--image_timestamps"}};
  guarded.output_folders = {{run.workspace_path, "--workspace_path"}};
  CheckOutputsApartFromInputs(guarded);
  ClaimOutputFolder(run.workspace_path,
                    ReconstructionWorkspaceEntries(),
                    ExistingOutputs::kReplaceOwn);

  // [1] Frame selection.
  const Trajectory odometry = ReadOdometry(inputs.odometry_path,
                                           inputs.odometry_format,
                                           inputs.odometry_time_unit,
                                           inputs.odometry_time_unit_given);
  CheckOdometrySpeed(odometry);
  std::vector<TimedImage> images;
  {
    StageClock clock(&progress, 1, "selecting frames with the odometry");
    const ImageTimestamps timestamps =
        inputs.image_timestamps_path.empty()
            ? ImageTimestamps::FromFileNames(inputs.file_name_time_unit)
            : ImageTimestamps::FromCsv(inputs.image_timestamps_path,
                                       inputs.image_time_unit);
    const std::vector<std::string> names = ListImages(run.image_path);
    if (names.empty()) {
      throw FormatError(run.image_path +
                        ": no images (.png, .jpg, .jpeg, "
                        ".bmp, .tif)");
    }
    std::vector<TimedImage> all;
    for (const std::string& name : names) {
      std::string why;
      const auto stamp = timestamps.Lookup(name, &why);
      if (!stamp) throw FormatError(run.image_path + "/" + name + ": " + why);
      all.push_back({name, *stamp});
    }
    if (inputs.image_timestamps_path.empty()) {
      std::vector<int64_t> stamps_ns;
      for (const TimedImage& image : all) stamps_ns.push_back(image.stamp_ns);
      CheckImageTimesAreNotFrameNumbers(
          stamps_ns, run.image_path, timestamps.how_read());
    }
    FrameSelectionOptions frames = run.frames;
    frames.max_odometry_gap_s = inputs.association.max_odometry_gap_s;
    frames.camera_time_offset_ns = inputs.association.camera_time_offset_ns;
    const FrameSelection selection = SelectFrames(all, odometry, frames);
    if (selection.kept.size() < 3) {
      throw FormatError(run.image_path + ": only " +
                        std::to_string(selection.kept.size()) + " of " +
                        std::to_string(names.size()) +
                        " images are inside the odometry and apart enough (" +
                        std::to_string(selection.num_outside_odometry) +
                        " outside its span or gaps)");
    }
    if (run.matcher == "sequential") {
      for (size_t i = 1; i < selection.kept.size(); ++i) {
        if (selection.kept[i].name < selection.kept[i - 1].name) {
          throw FormatError(
              "image names do not sort in time order (" +
              selection.kept[i - 1].name + " after " + selection.kept[i].name +
              "); the sequential matcher needs that: use --matcher spatial");
        }
      }
    }
    std::ostringstream list;
    for (const TimedImage& image : selection.kept) list << image.name << "\n";
    WriteFileAtomically((workspace / "image_list.txt").string(), list.str());
    images = selection.kept;
    clock.Done("kept " + std::to_string(selection.kept.size()) + " of " +
               std::to_string(selection.num_images) + " images (" +
               std::to_string(selection.num_dropped_still_or_close) +
               " standing still or too close, " +
               std::to_string(selection.num_outside_odometry) +
               " outside the odometry)");
  }

  // Before COLMAP: whether the odometry between the image times can
  // determine the calibration at all (excitation_precheck.h).
  std::vector<int64_t> image_stamps;
  for (const TimedImage& image : images) image_stamps.push_back(image.stamp_ns);
  const ExcitationPrecheck precheck = PrecheckExcitation(
      image_stamps, odometry, inputs.association, inputs.calibration);
  progress.Note(1, ExcitationLine(precheck, inputs.calibration, run.force));
  ReconstructionResult result;
  if (!precheck.determinable && !run.force) {
    // The solver's status and `unobservable` (no estimate).
    result.refused_before_colmap = true;
    CalibrationResult& refused = result.calibration.check.result;
    refused = precheck.verdict;
    refused.message +=
        " (seen in the odometry at the image times, before COLMAP; --force "
        "runs it anyway)";
    result.calibration.association = precheck.association;
    return result;
  }

  ColmapRunner::Options runner_options;
  runner_options.executable = run.colmap_path;
  runner_options.workspace = run.workspace_path;
  ColmapRunner colmap(runner_options);
  const ColmapVersion& version = colmap.Version();

  // [2] Features.
  const std::string database = (workspace / "database.db").string();
  const std::string extraction = FeatureExtractionPrefix(version);
  {
    StageClock clock(&progress, 2, "COLMAP feature extraction");
    std::vector<std::string> arguments = {
        "feature_extractor",
        "--database_path",
        database,
        "--image_path",
        run.image_path,
        "--image_list_path",
        (workspace / "image_list.txt").string(),
        "--ImageReader.single_camera",
        "1",
        "--ImageReader.camera_model",
        run.camera_model,
        "--" + extraction + ".use_gpu",
        "0",
        "--" + extraction + ".max_num_features",
        std::to_string(run.max_num_features),
        "--" + extraction + ".num_threads",
        std::to_string(run.num_threads)};
    if (!run.camera_params.empty()) {
      arguments.insert(arguments.end(),
                       {"--ImageReader.camera_params", run.camera_params});
    }
    const ColmapStageResult stage =
        colmap.RunStage("feature_extractor", arguments, {database});
    CheckImagesWereRead(database,
                        images.size(),
                        run.image_path,
                        stage.log_path,
                        workspace / "stages" / "feature_extractor.done");
    clock.Done(Note(stage));
  }

  // [3] Matching, guided by odometry positions.
  std::string matcher = run.matcher;
  if (matcher == "spatial" && version.AtLeast(3, 10)) {
    progress.Note(
        2, "(COLMAP >= 3.10 keeps priors elsewhere: sequential matching)");
    matcher = "sequential";
  }
  if (matcher == "spatial") {
    std::map<std::string, Eigen::Vector3d> positions;
    InterpolationFailure why;
    const double max_gap_s =
        OdometryGapLimitS(inputs.association.max_odometry_gap_s, odometry);
    for (const TimedImage& image : images) {
      const auto pose = InterpolateOdometry(
          odometry,
          image.stamp_ns + inputs.association.camera_time_offset_ns,
          max_gap_s,
          &why);
      if (pose) positions[image.name] = pose->translation;
    }
    WriteColmapDatabasePositionPriors(database, positions);
  }
  std::vector<MatchingRound> rounds(1);
  rounds[0].database = database;
  {
    StageClock clock(&progress, 3, "COLMAP " + matcher + " matching");
    clock.Done(
        Note(colmap.RunStage(matcher + "_matcher",
                             MatcherArguments(matcher, rounds[0], run, version),
                             {database})));
  }

  // [4] Mapping, each model checked against the odometry; when the random
  // seeds do not help, [3] and [4] once more on new matches
  // (mapper_policy.h).
  for (MapperStep step = policy.Next(); step.kind != MapperStep::Kind::kDone;
       step = policy.Next()) {
    if (step.kind == MapperStep::Kind::kMatchAgain) {
      MatchingRound again;
      again.index = step.matching_round;
      again.database = (workspace / "database_rematched.db").string();
      MatchAgain(&colmap, matcher, again, database, run, &progress);
      rounds.push_back(again);
      policy.MatchedAgain();
      continue;
    }
    MapWithSeed(&colmap,
                run,
                rounds.at(step.matching_round),
                step.random_seed,
                &progress,
                &policy);
  }
  const std::vector<MapperAttempt>& attempts = policy.attempts();
  const int chosen = policy.Best();
  if (chosen < 0) {
    throw ColmapError("COLMAP mapper produced no model in " +
                      std::to_string(attempts.size()) +
                      (attempts.size() == 1 ? " run" : " runs") + " (see " +
                      (workspace / "logs" / "mapper_seed_0.log").string() +
                      "): too little texture or overlap, or wrong intrinsics");
  }

  // [5] Calibration of the model the odometry contradicts least.
  const MapperAttempt& best = attempts[chosen];
  StageClock clock(&progress,
                   5,
                   "calibrating against the odometry (model of " +
                       MapperAttemptName(best) + ")");
  const fs::path sparse = workspace / "sparse";
  ReplaceWithCopy(best.model_path, run.workspace_path, "sparse");
  // Calibrated again (a fraction of a second) so that every path in the
  // outputs names sparse/, the model a later `odomcal colmap` would read.
  ColmapCalibrationInputs final_inputs = inputs;
  final_inputs.model_path = sparse.string();
  final_inputs.database_path = rounds.at(best.matching_round).database;
  result.model_path = final_inputs.model_path;
  result.database_path = final_inputs.database_path;
  result.calibration = CalibrateColmapProject(final_inputs);
  result.calibration.mapper_attempts = attempts;
  result.calibration.chosen_mapper_attempt = chosen;
  if (const auto warning = policy.ContradictionWarning()) {
    result.calibration.check.result.warnings.push_back(*warning);
  }
  clock.Done("calibrated");
  return result;
}

}  // namespace odomcal
