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
#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/colmap_model_subset.h"
#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/image_timestamps.h"
#include "odomcal/adapters/input_plausibility.h"
#include "odomcal/adapters/text_reader.h"
#include "odomcal/plugin/colmap_progress.h"
#include "odomcal/plugin/colmap_runner.h"
#include "odomcal/plugin/fold_reposing.h"
#include "odomcal/plugin/image_coverage.h"
#include "odomcal/plugin/mapper_stretches.h"
#include "odomcal/plugin/odometry_inputs.h"
#include "odomcal/plugin/output_file.h"
#include "odomcal/plugin/output_folder.h"
#include "odomcal/plugin/output_guard.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/format_number.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

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
// fraction that never decreases (stages 3 and 4 may run again), and, while a
// COLMAP stage runs, what COLMAP prints about its progress (at most once a
// second).
class Progress {
 public:
  explicit Progress(const ProgressCallback& callback) : callback_(callback) {}

  void Send(PipelineProgress::Event event,
            int stage,
            const std::string& message,
            double seconds = 0.0,
            double stage_fraction = 0.0) {
    PipelineProgress progress;
    progress.event = event;
    progress.stage = stage;
    progress.num_stages = kReconstructionStages;
    double done = stage;
    if (event == PipelineProgress::Event::kStageStarted) {
      done = stage - 1;
      live_stage_ = stage;
      live_ = ColmapOutputProgress(num_images_);
      live_start_ = std::chrono::steady_clock::now();
      live_sent_ = live_start_ - std::chrono::seconds(1);
    } else if (event == PipelineProgress::Event::kStageProgress) {
      done = stage - 1 + std::clamp(stage_fraction, 0.0, 1.0);
    }
    fraction_ = std::max(fraction_, done / kReconstructionStages);
    progress.fraction = fraction_;
    progress.message = message;
    progress.seconds = seconds;
    if (callback_) callback_(progress);
  }

  void Note(int stage, const std::string& message) {
    Send(PipelineProgress::Event::kNote, stage, message);
  }

  // The images COLMAP works on (the mapper's fraction).
  void SetNumImages(int num_images) { num_images_ = num_images; }

  // The current stage's COLMAP run started at `start` (before the stage's
  // title: a chunk mapped beside others): its elapsed time and time left
  // count from there.
  void SetLiveStart(std::chrono::steady_clock::time_point start) {
    live_start_ = std::min(live_start_, start);
  }

  // A line COLMAP printed during the current stage.
  void ColmapLine(const std::string& line) {
    if (!callback_ || !live_.Feed(line)) return;
    const auto now = std::chrono::steady_clock::now();
    if (now - live_sent_ < std::chrono::seconds(1)) return;
    live_sent_ = now;
    const double elapsed =
        std::chrono::duration<double>(now - live_start_).count();
    Send(PipelineProgress::Event::kStageProgress,
         live_stage_,
         live_.Describe(elapsed),
         elapsed,
         std::max(0.0, live_.Fraction()));
  }

 private:
  const ProgressCallback& callback_;
  double fraction_ = 0.0;
  int num_images_ = 0;
  int live_stage_ = 0;
  ColmapOutputProgress live_;
  std::chrono::steady_clock::time_point live_start_, live_sent_;
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
  // `seconds`: the stage's own time when it ran beside others (a chunk's
  // mapper), instead of the time since this clock started.
  void Done(const std::string& note, std::optional<double> seconds = {}) {
    progress_->Send(PipelineProgress::Event::kStageFinished,
                    index_,
                    note,
                    seconds.value_or(Seconds()));
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

// One matching of the images and the mapper runs on it.
struct MatchingRound {
  int index = 0;  // MapperAttempt::matching_round
  std::string database;
};

// --matcher odometry: the pairs chosen from the odometry
// (OdometryCandidatePairs), one "name1 name2" per line.
constexpr const char* kOdometryPairsFile = "odometry_pairs.txt";

std::vector<std::string> MatcherArguments(const std::string& matcher,
                                          const MatchingRound& round,
                                          const ReconstructionOptions& run,
                                          const ColmapVersion& version) {
  const std::string matching = FeatureMatchingPrefix(version);
  std::vector<std::string> arguments = {
      matcher == "odometry" ? "matches_importer" : matcher + "_matcher",
      "--database_path",
      round.database,
      "--" + matching + ".use_gpu",
      "0",
      "--" + matching + ".num_threads",
      std::to_string(run.num_threads)};
  if (matcher == "odometry") {
    arguments.insert(
        arguments.end(),
        {"--match_list_path",
         (fs::path(run.workspace_path) / kOdometryPairsFile).string(),
         "--match_type",
         "pairs"});
  } else if (matcher == "spatial") {
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

// Where `colmap mapper` run as stage "mapper_<entry>" writes its
// sub-models: mapper_attempts/<entry> in the workspace.
fs::path MapperOutput(const ReconstructionOptions& run,
                      const std::string& entry) {
  return fs::path(run.workspace_path) / "mapper_attempts" / entry;
}

// `colmap mapper` on `database`'s matches of the images in `image_list`,
// with the intrinsics kept fixed when given (--camera_params), and
// --random_seed when `random_seed` holds one.
std::vector<std::string> MapperArguments(const ReconstructionOptions& run,
                                         const std::string& database,
                                         const fs::path& output,
                                         const fs::path& image_list,
                                         std::optional<int> random_seed,
                                         int num_threads) {
  const bool fixed_intrinsics = !run.camera_params.empty();
  std::vector<std::string> arguments = {"mapper",
                                        "--database_path",
                                        database,
                                        "--image_path",
                                        run.image_path,
                                        "--output_path",
                                        output.string(),
                                        "--image_list_path",
                                        image_list.string()};
  if (random_seed) {
    arguments.insert(arguments.end(),
                     {"--random_seed", std::to_string(*random_seed)});
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

// Starts `arguments` (MapperArguments into MapperOutput(run, entry)) as
// stage "mapper_<entry>". Unless the stage is reused, its output folder is
// emptied first: a rerun must not mix new sub-models with stale ones.
RunningStage StartMapper(ColmapRunner* colmap,
                         const ReconstructionOptions& run,
                         const std::string& entry,
                         const std::vector<std::string>& arguments) {
  const std::string stage = "mapper_" + entry;
  const fs::path output = MapperOutput(run, entry);
  const std::vector<std::string> outputs = {(output / "0").string()};
  if (!colmap->WillReuse(stage, arguments, outputs)) {
    RemoveOwnedOutput(run.workspace_path, "mapper_attempts/" + entry);
  }
  std::error_code error;
  fs::create_directories(output, error);
  return colmap->StartStage(stage, arguments, outputs);
}

// StartMapper, waited for (COLMAP's lines to the runner's listener).
ColmapStageResult RunMapper(ColmapRunner* colmap,
                            const ReconstructionOptions& run,
                            const std::string& entry,
                            const std::vector<std::string>& arguments) {
  RunningStage stage = StartMapper(colmap, run, entry, arguments);
  stage.WaitForEnd(colmap->options().on_output_line);
  return stage.Finish();
}

// Whether a mapper run into `output` produced a model.
bool HasModel(const fs::path& output) { return fs::exists(output / "0"); }

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

// Mapper runs on independent image sets (the chunks of a drive) side by
// side: queued, at most `at_once` going at a time, started in queue order
// (or first, when queued so), each waited for when its turn comes while the
// others go on. A run no longer needed is cancelled; runs still going when
// the queue is destroyed (not waited for, or an exception) are stopped.
class MapperQueue {
 public:
  using StartedCallback =
      std::function<void(std::chrono::steady_clock::time_point)>;

  MapperQueue(ColmapRunner* colmap,
              const ReconstructionOptions& run,
              int at_once)
      : colmap_(colmap), run_(run), at_once_(std::max(1, at_once)) {}

  // Queues MapperArguments into MapperOutput(run, entry), to be started
  // after those queued before it, or before them with `first`; its index.
  size_t Add(const std::string& entry,
             std::vector<std::string> arguments,
             bool first = false) {
    runs_.push_back({entry, std::move(arguments), std::nullopt, false});
    if (first) {
      waiting_.push_front(runs_.size() - 1);
    } else {
      waiting_.push_back(runs_.size() - 1);
    }
    return runs_.size() - 1;
  }

  // Run `i` is not needed: not started, or stopped.
  void Cancel(size_t i) {
    waiting_.erase(std::remove(waiting_.begin(), waiting_.end(), i),
                   waiting_.end());
    runs_[i].stage.reset();
    runs_[i].ended = true;
  }

  // Waits for run `i` (not cancelled) to end: its COLMAP lines to
  // `on_line`, its start time to `on_started` once it started; meanwhile
  // queued runs start whenever fewer than `at_once` are going.
  RunningStage& WaitFor(size_t i,
                        const OutputLineCallback& on_line,
                        const StartedCallback& on_started) {
    bool told = false;
    for (;;) {
      while (!waiting_.empty() && Going() < at_once_) {
        Run& next = runs_[waiting_.front()];
        waiting_.pop_front();
        next.stage = StartMapper(colmap_, run_, next.entry, next.arguments);
      }
      if (!told && runs_[i].stage) {
        on_started(runs_[i].stage->started());
        told = true;
      }
      bool any_ended = false;
      for (size_t k = 0; k < runs_.size(); ++k) {
        Run& run = runs_[k];
        if (!run.stage || run.ended) continue;
        run.ended = run.stage->Poll(k == i ? on_line : OutputLineCallback());
        any_ended = any_ended || run.ended;
      }
      if (runs_[i].stage && runs_[i].ended) return *runs_[i].stage;
      if (!any_ended) {
        std::this_thread::sleep_for(std::chrono::milliseconds(250));
      }
    }
  }

 private:
  struct Run {
    std::string entry;
    std::vector<std::string> arguments;
    std::optional<RunningStage> stage;  // once started
    bool ended = false;
  };
  int Going() const {
    return static_cast<int>(
        std::count_if(runs_.begin(), runs_.end(), [](const Run& run) {
          return run.stage && !run.ended;
        }));
  }

  ColmapRunner* colmap_;
  const ReconstructionOptions& run_;
  int at_once_;
  std::vector<Run> runs_;
  std::deque<size_t> waiting_;  // queued, not started, in start order
};

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
  const std::string entry = prefix + "seed_" + std::to_string(seed);
  const fs::path output = MapperOutput(run, entry);
  const ColmapStageResult stage =
      RunMapper(colmap,
                run,
                entry,
                MapperArguments(run,
                                round.database,
                                output,
                                workspace / "image_list.txt",
                                seed,
                                run.num_threads));
  attempt.model_path = output.string();
  if (!HasModel(output)) {
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

// "images 86-300".
std::string ImageRange(int first, int last) {
  return "images " + std::to_string(first + 1) + "-" + std::to_string(last + 1);
}

// [4] for the stretches the chosen model left out: each stretch of at least
// kMinStretchModelImages unregistered images is matched along the odometry
// (OdometryCandidatePairs: a baseline the nearest-neighbour matching lacks)
// and mapped on its own, starting from a pair the odometry chooses
// (ChooseInitialPair) with relaxed initialisation thresholds, and without a
// given pair when that fails. Returns the mapper output folders with a model;
// each becomes sub-models (segments with scales of their own) beside the
// chosen model's.
std::vector<fs::path> MapUnregisteredStretches(
    ColmapRunner* colmap,
    const ReconstructionOptions& run,
    const std::vector<TimedImage>& images,
    const Trajectory& odometry,
    const MapperAttempt& best,
    const std::string& database,
    Progress* progress) {
  const ColmapCalibrationInputs& inputs = run.project;
  ColmapCalibrationInputs best_inputs = inputs;
  best_inputs.model_path = best.model_path;
  best_inputs.database_path = database;
  const ColmapCalibrationRun calibrated = CalibrateColmapProject(best_inputs);
  const std::set<std::string> registered = RegisteredImages(calibrated);
  const ImageCoverage coverage = SummarizeImageCoverage(
      images,
      registered,
      ImagesInCalibration(calibrated,
                          calibrated.systematics.camera_time_offset_ns));
  std::map<std::string, uint32_t> image_ids;
  for (const ColmapDatabaseImage& image : ReadColmapDatabaseImages(database)) {
    image_ids[image.name] = image.image_id;
  }
  const fs::path workspace(run.workspace_path);
  std::error_code error;
  fs::create_directories(workspace / "stretches", error);
  const std::string matching = FeatureMatchingPrefix(colmap->Version());
  std::vector<fs::path> models;
  int index = 0;
  for (const CoverageStretch& stretch : coverage.stretches) {
    if (stretch.in_calibration) continue;
    std::vector<int> members;  // unregistered images of the stretch
    std::vector<Rigid3d> poses;
    for (int i = stretch.first_image; i <= stretch.last_image; ++i) {
      if (registered.count(images[i].name) > 0) continue;
      InterpolationFailure why;
      const auto pose = InterpolateOdometry(
          odometry,
          images[i].stamp_ns + inputs.association.camera_time_offset_ns,
          OdometryGapLimitS(inputs.association.max_odometry_gap_s, odometry),
          &why);
      if (!pose || image_ids.count(images[i].name) == 0) continue;
      members.push_back(i);
      poses.push_back(*pose);
    }
    if (static_cast<int>(members.size()) < kMinStretchModelImages) continue;
    const std::string name = "stretch_" + std::to_string(index++);
    const std::string range =
        ImageRange(stretch.first_image, stretch.last_image);
    // Matches with a baseline, added to the database (pairs matched before
    // are skipped by COLMAP).
    const std::vector<std::pair<int, int>> pairs =
        OdometryCandidatePairs(poses, run.candidate_pairs);
    std::ostringstream pair_list, image_list;
    for (const auto& [a, b] : pairs) {
      pair_list << images[members[a]].name << " " << images[members[b]].name
                << "\n";
    }
    for (const int i : members) image_list << images[i].name << "\n";
    const fs::path pairs_path = workspace / "stretches" / (name + "_pairs.txt");
    const fs::path list_path = workspace / "stretches" / (name + "_images.txt");
    WriteFileAtomically(pairs_path.string(), pair_list.str());
    WriteFileAtomically(list_path.string(), image_list.str());
    {
      StageClock clock(progress,
                       3,
                       "COLMAP matching " + std::to_string(pairs.size()) +
                           " odometry pairs in the unregistered " + range);
      // A stretch is extra: COLMAP failing on it (e.g. a CHECK on images
      // without features) leaves it out and the run goes on.
      try {
        clock.Done(Note(colmap->RunStage("matches_importer_" + name,
                                         {"matches_importer",
                                          "--database_path",
                                          database,
                                          "--match_list_path",
                                          pairs_path.string(),
                                          "--match_type",
                                          "pairs",
                                          "--" + matching + ".use_gpu",
                                          "0",
                                          "--" + matching + ".num_threads",
                                          std::to_string(run.num_threads)},
                                         {database})));
      } catch (const ColmapError& failure) {
        clock.Done(std::string("left out: ") + failure.what());
        continue;
      }
    }
    const std::optional<std::pair<int, int>> initial =
        ChooseInitialPair(poses, pairs, run.initial_pair);
    // With the odometry's initial pair first, then COLMAP's own choice.
    for (const bool given_pair : {true, false}) {
      if (given_pair && !initial) continue;
      const std::string entry = name + (given_pair ? "" : "_free");
      const fs::path output = MapperOutput(run, entry);
      std::vector<std::string> arguments = MapperArguments(
          run, database, output, list_path, std::nullopt, run.num_threads);
      // The default 16 deg and 0.95 refuse what a robot driving ahead
      // sees; the odometry checks the model that results.
      arguments.insert(arguments.end(),
                       {"--Mapper.init_min_tri_angle",
                        "8",
                        "--Mapper.init_max_forward_motion",
                        "0.99"});
      std::string from = "COLMAP's choice of initial pair";
      if (given_pair) {
        const std::string& first = images[members[initial->first]].name;
        const std::string& second = images[members[initial->second]].name;
        arguments.insert(arguments.end(),
                         {"--Mapper.init_image_id1",
                          std::to_string(image_ids.at(first)),
                          "--Mapper.init_image_id2",
                          std::to_string(image_ids.at(second))});
        from = "the odometry's initial pair " + first + ", " + second;
      }
      progress->SetNumImages(static_cast<int>(members.size()));
      StageClock clock(progress,
                       4,
                       "COLMAP mapping the unregistered " + range + " (" +
                           std::to_string(members.size()) + " images) from " +
                           from);
      const std::optional<ColmapStageResult> result =
          RunExtraMapper(colmap, run, entry, arguments, &clock);
      if (!result) continue;
      size_t num_registered = 0;
      const std::vector<std::string> folders =
          FindColmapModelFolders(output.string());
      for (const std::string& folder : folders) {
        ColmapReadOptions read;
        read.read_points3D = false;
        num_registered += ReadColmapModel(folder, read).images.size();
      }
      clock.Done(Note(*result) + "; " + std::to_string(folders.size()) +
                 " sub-model(s), " + std::to_string(num_registered) +
                 " images registered");
      models.push_back(output);
      break;
    }
  }
  progress->SetNumImages(static_cast<int>(images.size()));
  return models;
}

// How many of the selected images made it into the calibration: in the
// result's message (the summary line), as a warning when too few, and per
// stretch in the run (the JSON's colmap.image_coverage).
void AddImageCoverage(const std::vector<TimedImage>& selected,
                      int64_t camera_time_offset_ns,
                      ColmapCalibrationRun* run) {
  run->coverage =
      SummarizeImageCoverage(selected,
                             RegisteredImages(*run),
                             ImagesInCalibration(*run, camera_time_offset_ns));
  CalibrationResult& result = run->check.result;
  result.message += "; " + CoverageClause(*run->coverage);
  if (const auto warning = CoverageWarning(*run->coverage)) {
    result.warnings.push_back(*warning);
  }
}

// The narrower field of view (horizontal or vertical) of the camera the run
// uses, for the frame selection's automatic thresholds: from
// --camera_params (f, cx, cy for the one-focal models, fx, fy, cx, cy for the
// others; a fisheye's field of view is wider, so its thresholds come out
// smaller), else that of COLMAP's default focal length.
double RunFieldOfViewDeg(const ReconstructionOptions& run) {
  if (run.camera_params.empty()) return kColmapDefaultFieldOfViewDeg;
  std::vector<double> params;
  std::stringstream text(run.camera_params);
  std::string field;
  while (std::getline(text, field, ',')) {
    params.push_back(std::strtod(field.c_str(), nullptr));
  }
  const auto model = ColmapCameraModelFromName(run.camera_model);
  if (!model) return kColmapDefaultFieldOfViewDeg;  // the flag check names it
  const bool one_focal = model == ColmapCameraModel::kSimplePinhole ||
                         model == ColmapCameraModel::kSimpleRadial ||
                         model == ColmapCameraModel::kRadial ||
                         model == ColmapCameraModel::kSimpleRadialFisheye ||
                         model == ColmapCameraModel::kRadialFisheye;
  const size_t fy = one_focal ? 0 : 1;
  const size_t cx = one_focal ? 1 : 2;
  const size_t cy = cx + 1;
  if (params.size() <= cy ||
      !std::all_of(params.begin(), params.begin() + cy + 1, [](double p) {
        return p > 0.0 && std::isfinite(p);
      })) {
    return kColmapDefaultFieldOfViewDeg;
  }
  return std::min(FieldOfViewDeg(params[0], params[cx]),
                  FieldOfViewDeg(params[fy], params[cy]));
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

// What a chunk's model kept: its sub-models, its images registered, and
// those of the chunk's own images (mapper_chunks.h).
struct ChunkCut {
  size_t num_folders = 0;
  size_t num_registered = 0;
  size_t num_kept = 0;
  int num_written = 0;  // sub-models written (those keeping 2+ own images)
};

// The sub-models of `output` (a mapper run on one chunk), cut to `own`,
// written as the numbered sub-models of `combined` from `first_sub_model`.
ChunkCut CutChunkModel(const fs::path& output,
                       const std::set<std::string>& own,
                       const fs::path& combined,
                       int first_sub_model) {
  ChunkCut cut;
  const std::vector<std::string> folders =
      FindColmapModelFolders(output.string());
  cut.num_folders = folders.size();
  for (const std::string& folder : folders) {
    const ColmapModel model = ReadColmapModel(folder);
    cut.num_registered += model.images.size();
    std::set<uint32_t> ids;
    for (const auto& [id, image] : model.images) {
      if (own.count(image.name) > 0) ids.insert(id);
    }
    if (ids.size() < 2) continue;
    cut.num_kept += ids.size();
    WriteColmapModel(
        ColmapModelSubset(model, ids),
        (combined / std::to_string(first_sub_model + cut.num_written++))
            .string(),
        ColmapFormat::kBinary);
  }
  return cut;
}

// A combination of chunk models: mapper_attempts/<entry>, its numbered
// sub-models, and the chunk each came from.
struct ChunkCombination {
  std::string entry;
  std::vector<int> chunk_of_sub_model;
};

// Emptied first: a rerun must not mix new sub-models with stale ones.
fs::path StartCombination(const ReconstructionOptions& run,
                          ChunkCombination* combination) {
  RemoveOwnedOutput(run.workspace_path, combination->entry);
  combination->chunk_of_sub_model.clear();
  const fs::path folder = fs::path(run.workspace_path) / combination->entry;
  std::error_code error;
  fs::create_directories(folder, error);
  return folder;
}

// Chunk k's model (`output`) cut and added to `combination`.
ChunkCut AddChunkModel(const fs::path& folder,
                       int k,
                       const fs::path& output,
                       const std::set<std::string>& own,
                       ChunkCombination* combination) {
  const ChunkCut cut =
      CutChunkModel(output,
                    own,
                    folder,
                    static_cast<int>(combination->chunk_of_sub_model.size()));
  combination->chunk_of_sub_model.insert(
      combination->chunk_of_sub_model.end(), cut.num_written, k);
  return cut;
}

// The chunks' models `outputs` (empty: none), each cut to the chunk's own
// images, as the combination `entry` (started anew).
ChunkCombination CombineChunkModels(
    const ReconstructionOptions& run,
    const std::string& entry,
    const std::vector<fs::path>& outputs,
    const std::vector<std::set<std::string>>& own) {
  ChunkCombination combination{entry, {}};
  const fs::path folder = StartCombination(run, &combination);
  for (size_t j = 0; j < outputs.size(); ++j) {
    if (outputs[j].empty()) continue;
    AddChunkModel(
        folder, static_cast<int>(j), outputs[j], own[j], &combination);
  }
  return combination;
}

ColmapCalibrationRun CalibrateCombination(const ReconstructionOptions& run,
                                          const MatchingRound& round,
                                          const ChunkCombination& combination) {
  ColmapCalibrationInputs inputs = run.project;
  inputs.model_path =
      (fs::path(run.workspace_path) / combination.entry).string();
  inputs.database_path = round.database;
  return CalibrateColmapProject(inputs);
}

// Per chunk, the motion pairs its sub-models lost to stretches left out as
// folded.
std::vector<int> FoldedPairsOfChunks(const ColmapCalibrationRun& calibration,
                                     const ChunkCombination& combination,
                                     size_t num_chunks) {
  std::vector<int> chunk_of_segment;
  for (const ColmapSegment& segment : calibration.segments) {
    // Sub-models are named by their number (StartCombination's folder);
    // any other name is from no chunk.
    const int sub_model = SubModelNumber(segment.sub_model);
    chunk_of_segment.push_back(
        sub_model >= 0 && sub_model < static_cast<int>(
                                          combination.chunk_of_sub_model.size())
            ? combination.chunk_of_sub_model[sub_model]
            : -1);
  }
  return FoldedPairsPerChunk(static_cast<int>(num_chunks),
                             chunk_of_segment,
                             calibration.check.stretches);
}

// A posed image must see at least this many triangulated points after the
// adjustment: COLMAP's mapper registers an image from 30 inliers
// (--Mapper.abs_pose_min_num_inliers).
constexpr int kMinPointsOfPosedImage = 30;

// Whether the files of model folders `a` and `b` are byte for byte the same
// (false when either is missing).
bool SameModelFiles(const fs::path& a, const fs::path& b) {
  for (const char* name : {"cameras.bin", "images.bin", "points3D.bin"}) {
    std::ifstream file_a(a / name, std::ios::binary);
    std::ifstream file_b(b / name, std::ios::binary);
    if (!file_a || !file_b) return false;
    const std::string bytes_a((std::istreambuf_iterator<char>(file_a)),
                              std::istreambuf_iterator<char>());
    const std::string bytes_b((std::istreambuf_iterator<char>(file_b)),
                              std::istreambuf_iterator<char>());
    if (bytes_a != bytes_b) return false;
  }
  return true;
}

// The earliest stretch of input segment `segment` left out as folded, with
// what posing it from the odometry needs from `calibration`; nothing without
// such a stretch or without an estimate.
std::optional<FoldToRepose> FoldOfSegment(
    const ColmapCalibrationRun& calibration, int segment) {
  const StretchCheckResult& check = calibration.check;
  if (!check.result.has_estimate) return std::nullopt;
  std::optional<FoldToRepose> fold;
  for (const InconsistentStretch& stretch : check.stretches) {
    if (stretch.kept_as_segment || stretch.input_segment != segment ||
        (fold && fold->first_stamp_ns <= stretch.first_stamp_ns)) {
      continue;
    }
    fold = FoldToRepose{};
    fold->first_stamp_ns = stretch.first_stamp_ns;
  }
  if (!fold) return std::nullopt;
  for (size_t o = 0; o < check.input_segment_of_output_segment.size(); ++o) {
    if (check.input_segment_of_output_segment[o] == segment) {
      fold->metres_per_unit = check.result.metric_scales.at(o);
      break;
    }
  }
  fold->camera_time_offset_ns = calibration.systematics.camera_time_offset_ns;
  fold->odom_from_cam = check.result.odom_from_cam;
  fold->max_odometry_gap_s = calibration.association.max_odometry_gap_s;
  return fold;
}

// Chunk k's sub-models in `chosen`, each with a stretch left out as folded
// posed again from the odometry (fold_reposing.h), then `colmap
// point_triangulator` and `colmap bundle_adjuster` on it (intrinsics held
// as the mapper holds them), written as chunk k's model
// mapper_attempts/<entry> (its other sub-models copied unchanged). Returns
// the number of sub-models posed again (0: none could be, or COLMAP failed
// on one; `why` says which).
int PoseChunkFoldsFromOdometry(ColmapRunner* colmap,
                               const ReconstructionOptions& run,
                               const MatchingRound& round,
                               const ColmapCalibrationRun& calibration,
                               const ChunkCombination& chosen,
                               size_t k,
                               const std::string& entry,
                               std::string* why) {
  const fs::path combined = fs::path(run.workspace_path) / chosen.entry;
  const fs::path root = MapperOutput(run, entry);
  std::error_code error;
  fs::create_directories(root, error);
  const bool fixed_intrinsics = !run.camera_params.empty();
  int num_written = 0;
  int num_posed = 0;
  std::vector<std::string> notes;
  for (size_t sub = 0; sub < chosen.chunk_of_sub_model.size(); ++sub) {
    if (chosen.chunk_of_sub_model[sub] != static_cast<int>(k)) continue;
    const fs::path source = combined / std::to_string(sub);
    const std::string number = std::to_string(num_written++);
    const fs::path target = root / number;
    int segment = -1;
    for (size_t i = 0; i < calibration.segments.size(); ++i) {
      if (calibration.segments[i].sub_model == std::to_string(sub)) {
        segment = static_cast<int>(i);
      }
    }
    const std::optional<FoldToRepose> fold =
        FoldOfSegment(calibration, segment);
    const std::optional<ReposedModel> reposed =
        fold ? ReposeFoldFromOdometry(ReadColmapModel(source.string()),
                                      calibration.segments[segment],
                                      calibration.odometry,
                                      *fold)
             : std::nullopt;
    const fs::path entry_path = fs::path("mapper_attempts") / entry;
    if (!reposed) {
      RemoveOwnedOutput(run.workspace_path, (entry_path / number).string());
      fs::copy(source, target, fs::copy_options::recursive);
      continue;
    }
    // Stage reuse compares the arguments, not the posed model they read: a
    // model posed differently (another calibration) runs both stages anew.
    const fs::path posed = root / ("posed_" + number);
    const fs::path posed_new = root / ("posed_" + number + ".new");
    const fs::path triangulated = root / ("triangulated_" + number);
    WriteColmapModel(reposed->model, posed_new.string(), ColmapFormat::kBinary);
    if (!SameModelFiles(posed, posed_new)) {
      for (const std::string& stale : {"triangulated_" + number, number}) {
        RemoveOwnedOutput(run.workspace_path, (entry_path / stale).string());
      }
      fs::remove_all(posed, error);
      fs::rename(posed_new, posed);
    } else {
      fs::remove_all(posed_new, error);
    }
    fs::create_directories(triangulated, error);
    fs::create_directories(target, error);
    const std::string stage = entry + "_" + number;
    try {
      colmap->RunStage("triangulate_" + stage,
                       {"point_triangulator",
                        "--database_path",
                        round.database,
                        "--image_path",
                        run.image_path,
                        "--input_path",
                        posed.string(),
                        "--output_path",
                        triangulated.string(),
                        "--clear_points",
                        "1"},
                       {(triangulated / "images.bin").string()});
      colmap->RunStage("adjust_" + stage,
                       {"bundle_adjuster",
                        "--input_path",
                        triangulated.string(),
                        "--output_path",
                        target.string(),
                        "--BundleAdjustment.refine_focal_length",
                        fixed_intrinsics ? "0" : "1",
                        "--BundleAdjustment.refine_principal_point",
                        "0",
                        "--BundleAdjustment.refine_extra_params",
                        fixed_intrinsics ? "0" : "1"},
                       {(target / "images.bin").string()});
    } catch (const ColmapError& failure) {
      *why = failure.what();
      return 0;
    }
    if (!DetectColmapModelFormat(target.string())) {
      *why = "colmap bundle_adjuster wrote no model to " + target.string();
      return 0;
    }
    // The images must hold their new poses on their own: where the
    // adjustment has too few points to move an image, its pose would be the
    // odometry's, and its motion pairs would agree with the odometry by
    // construction.
    const ColmapModel adjusted = ReadColmapModel(target.string());
    for (const uint32_t id : reposed->reposed_image_ids) {
      const auto image = adjusted.images.find(id);
      int observations = 0;
      if (image != adjusted.images.end()) {
        for (const ColmapPoint2D& point : image->second.points2D) {
          observations += point.point3D_id != kColmapNoPoint3D ? 1 : 0;
        }
      }
      if (observations < kMinPointsOfPosedImage) {
        *why = reposed->model.images.at(id).name + " sees only " +
               std::to_string(observations) +
               " triangulated points after the adjustment (COLMAP's mapper "
               "registers an image from " +
               std::to_string(kMinPointsOfPosedImage) + ")";
        return 0;
      }
    }
    ++num_posed;
    notes.push_back(std::to_string(reposed->num_reposed) + " images from " +
                    reposed->anchor_image + " on");
  }
  // Sub-models a run before this one wrote beyond this chunk's.
  std::vector<std::string> stale;
  for (const auto& item : fs::directory_iterator(root, error)) {
    const std::string name = item.path().filename().string();
    if (SubModelNumber(name) >= num_written) stale.push_back(name);
  }
  for (const std::string& name : stale) {
    RemoveOwnedOutput(run.workspace_path,
                      (fs::path("mapper_attempts") / entry / name).string());
  }
  if (num_posed == 0) {
    *why = "no folded stretch of it starts at an image with an odometry pose";
  } else {
    std::string list;
    for (const std::string& note : notes) {
      list += (list.empty() ? "" : "; ") + note;
    }
    *why = list;
  }
  return num_posed;
}

struct ChunkedMapping {
  std::vector<MapperAttempt> attempts;  // all chunks, then each chunk again
  int chosen = -1;                      // -1: no chunk gave a model
};

// [4] for a drive longer than one chunk (mapper_chunks.h): each chunk
// mapped (--random_seed 0) on the round's matches, and the sub-models of
// every chunk, cut to the chunk's own images, written as numbered
// sub-models of mapper_attempts/chunks (segments with their own scale).
// A chunk in which the calibration leaves a stretch out as folded is mapped
// again with the next seeds (up to --mapper_attempts runs, until a seed does
// not help), each new combination written to
// mapper_attempts/chunks_<k>_seed_<s> and kept when more motion pairs of the
// drive agree with the odometry. Chunks are taken in order: one before a
// chunk mapped again is not revisited (its fold, if the new fit showed one
// there, would be the neighbour's scale, not its own). A chunk COLMAP fails
// on is left out; the stretches it leaves unregistered are mapped again
// later (MapUnregisteredStretches).
ChunkedMapping MapInChunks(ColmapRunner* colmap,
                           const ReconstructionOptions& run,
                           const MatchingRound& round,
                           const std::vector<TimedImage>& images,
                           const std::vector<MapperChunk>& chunks,
                           Progress* progress) {
  const fs::path workspace(run.workspace_path);
  std::error_code error;
  fs::create_directories(workspace / "chunks", error);
  std::vector<std::set<std::string>> own(chunks.size());
  std::vector<fs::path> lists(chunks.size());
  std::vector<fs::path> outputs(chunks.size());  // empty: no model
  // Chunks are independent, and COLMAP's mapper keeps about one core busy
  // on one (docs/benchmarks.md: 27 s of CPU in 24 s with two threads): so
  // up to --num_threads chunks are mapped side by side, the threads shared
  // among them (one each when there are at least as many chunks).
  const int at_once =
      std::clamp(run.num_threads, 1, static_cast<int>(chunks.size()));
  const int threads_each = std::max(1, run.num_threads / at_once);
  auto chunk_arguments = [&](size_t k, int seed, const std::string& name) {
    return MapperArguments(run,
                           round.database,
                           MapperOutput(run, name),
                           lists[k],
                           seed,
                           threads_each);
  };
  const OutputLineCallback live = [progress](const std::string& line) {
    progress->ColmapLine(line);
  };
  const MapperQueue::StartedCallback live_start =
      [progress](std::chrono::steady_clock::time_point start) {
        progress->SetLiveStart(start);
      };
  // Chunk k's run `i` of `queue` (mapped into mapper_attempts/<name>), once
  // it ended: its output folder (empty without a model), the stage's note
  // and the run's own time.
  struct ChunkRun {
    fs::path output;
    std::string note;
    double seconds = 0.0;
  };
  auto take_chunk = [&](MapperQueue* queue,
                        size_t i,
                        const std::string& name,
                        StageClock* clock) {
    RunningStage& stage = queue->WaitFor(i, live, live_start);
    const std::optional<ColmapStageResult> result =
        FinishExtraMapper(&stage, run, name, clock);
    return result ? ChunkRun{MapperOutput(run, name),
                             Note(*result),
                             stage.seconds()}
                  : ChunkRun{fs::path(), std::string(), stage.seconds()};
  };
  ChunkCombination chosen{"mapper_attempts/chunks", {}};
  const fs::path folder = StartCombination(run, &chosen);
  MapperQueue queue(colmap, run, at_once);
  std::vector<size_t> in_queue;  // chunk k's run in `queue`
  for (size_t k = 0; k < chunks.size(); ++k) {
    const MapperChunk& chunk = chunks[k];
    const std::string name = "chunk_" + std::to_string(k);
    std::ostringstream list;
    for (int i = chunk.first; i <= chunk.last; ++i) {
      list << images[i].name << "\n";
    }
    for (int i = chunk.own_first; i <= chunk.own_last; ++i) {
      own[k].insert(images[i].name);
    }
    lists[k] = workspace / "chunks" / (name + "_images.txt");
    WriteFileAtomically(lists[k].string(), list.str());
    in_queue.push_back(queue.Add(name, chunk_arguments(k, 0, name)));
  }
  const auto mapping_start = std::chrono::steady_clock::now();
  double mapper_seconds = 0.0;
  for (size_t k = 0; k < chunks.size(); ++k) {
    const MapperChunk& chunk = chunks[k];
    progress->SetNumImages(chunk.last - chunk.first + 1);
    StageClock clock(progress,
                     4,
                     "COLMAP mapping chunk " + std::to_string(k + 1) + " of " +
                         std::to_string(chunks.size()) + " (" +
                         ImageRange(chunk.first, chunk.last) + ")");
    const ChunkRun mapped =
        take_chunk(&queue, in_queue[k], "chunk_" + std::to_string(k), &clock);
    mapper_seconds += mapped.seconds;
    if (mapped.output.empty()) continue;
    outputs[k] = mapped.output;
    const ChunkCut cut = AddChunkModel(
        folder, static_cast<int>(k), mapped.output, own[k], &chosen);
    clock.Done(mapped.note + "; " + std::to_string(cut.num_folders) +
                   " sub-model(s), " + std::to_string(cut.num_registered) +
                   " of " + std::to_string(chunk.last - chunk.first + 1) +
                   " images registered, " + std::to_string(cut.num_kept) +
                   " of the chunk's own " +
                   std::to_string(chunk.own_last - chunk.own_first + 1) +
                   " kept",
               mapped.seconds);
  }
  if (at_once > 1) {
    progress->Note(
        4,
        "    " + std::to_string(chunks.size()) + " chunks mapped, " +
            std::to_string(at_once) + " side by side (--num_threads " +
            std::to_string(run.num_threads) + "), in " +
            FormatRounded(std::chrono::duration<double>(
                              std::chrono::steady_clock::now() - mapping_start)
                              .count()) +
            " s (their runs: " + FormatRounded(mapper_seconds) + " s)");
  }

  ChunkedMapping mapping;
  if (chosen.chunk_of_sub_model.empty()) {
    progress->SetNumImages(static_cast<int>(images.size()));
    return mapping;
  }
  ColmapCalibrationRun calibration = CalibrateCombination(run, round, chosen);
  auto summarize =
      [&](int seed, const ChunkCombination& combination, int chunk) {
        MapperAttempt attempt =
            SummarizeMapperAttempt(seed,
                                   (workspace / combination.entry).string(),
                                   calibration.segments,
                                   calibration.check);
        attempt.matching_round = round.index;
        attempt.chunk = chunk;
        return attempt;
      };
  mapping.attempts.push_back(summarize(0, chosen, -1));
  mapping.chosen = 0;
  std::vector<int> folded =
      FoldedPairsOfChunks(calibration, chosen, chunks.size());
  // A chunk with a fold is first posed again from the odometry where the
  // fold starts (seconds, where a mapper run takes minutes, and it escapes
  // folds that no seed does: fold_reposing.h); the new model is kept when
  // fewer motion pairs are left out as folded and no fewer are used.
  for (size_t k = 0; k < chunks.size(); ++k) {
    if (folded[k] == 0) continue;
    StageClock clock(progress,
                     4,
                     "COLMAP chunk " + std::to_string(k + 1) +
                         ": the folded stretch posed from the odometry, "
                         "triangulated and adjusted again (" +
                         std::to_string(folded[k]) +
                         " motion pairs of it left out as folded)");
    const std::string entry =
        "chunk_" + std::to_string(k) + "_posed_from_odometry";
    std::string why;
    if (PoseChunkFoldsFromOdometry(
            colmap, run, round, calibration, chosen, k, entry, &why) == 0) {
      clock.Done("not posed: " + why);
      continue;
    }
    std::vector<fs::path> candidate = outputs;
    candidate[k] = MapperOutput(run, entry);
    const ChunkCombination combination = CombineChunkModels(
        run,
        "mapper_attempts/chunks_" + std::to_string(k) + "_posed_from_odometry",
        candidate,
        own);
    ColmapCalibrationRun posed_calibration;
    try {
      posed_calibration = CalibrateCombination(run, round, combination);
    } catch (const FormatError& failure) {
      clock.Done(why + "; left out: " + failure.what());
      continue;
    }
    MapperAttempt attempt =
        SummarizeMapperAttempt(0,
                               (workspace / combination.entry).string(),
                               posed_calibration.segments,
                               posed_calibration.check);
    attempt.matching_round = round.index;
    attempt.chunk = static_cast<int>(k);
    attempt.posed_from_odometry = true;
    mapping.attempts.push_back(attempt);
    const MapperAttempt& best = mapping.attempts[mapping.chosen];
    const std::string pairs =
        std::to_string(attempt.num_pairs_left_out) +
        " motion pairs of the drive left out as folded (was " +
        std::to_string(best.num_pairs_left_out) + "), " +
        std::to_string(attempt.num_pairs_used) + " of " +
        std::to_string(attempt.num_pairs) + " used (was " +
        std::to_string(best.num_pairs_used) + ")";
    if (attempt.num_pairs_left_out >= best.num_pairs_left_out ||
        attempt.num_pairs_used < best.num_pairs_used) {
      clock.Done(why + "; " + pairs + ": not better");
      continue;
    }
    outputs = candidate;
    chosen = combination;
    calibration = std::move(posed_calibration);
    mapping.chosen = static_cast<int>(mapping.attempts.size()) - 1;
    folded = FoldedPairsOfChunks(calibration, chosen, chunks.size());
    clock.Done(why + "; " + pairs + ": this model kept");
  }
  // Every chunk with a fold now is mapped again with seed 1: those runs go
  // side by side from the start, and one whose fold an earlier chunk's new
  // model takes away is cancelled. Later seeds, and seed 1 of a fold that
  // only an earlier chunk's new model shows, are queued first when their
  // turn comes.
  MapperQueue retries(colmap, run, at_once);
  std::vector<std::optional<size_t>> first_retry(chunks.size());
  for (size_t k = 0; k < chunks.size(); ++k) {
    if (folded[k] == 0 || run.mapper.max_seeds < 2) continue;
    const std::string name = "chunk_" + std::to_string(k) + "_seed_1";
    first_retry[k] = retries.Add(name, chunk_arguments(k, 1, name));
  }
  for (size_t k = 0; k < chunks.size(); ++k) {
    for (int seed = 1; folded[k] > 0 && seed < run.mapper.max_seeds; ++seed) {
      const std::string suffix =
          std::to_string(k) + "_seed_" + std::to_string(seed);
      progress->SetNumImages(chunks[k].last - chunks[k].first + 1);
      StageClock clock(progress,
                       4,
                       "COLMAP mapping chunk " + std::to_string(k + 1) +
                           " again, --random_seed " + std::to_string(seed) +
                           " (" + std::to_string(folded[k]) +
                           " motion pairs of it left out as folded)");
      const std::string name = "chunk_" + suffix;
      const size_t index =
          seed == 1 && first_retry[k]
              ? *first_retry[k]
              : retries.Add(name, chunk_arguments(k, seed, name), true);
      const ChunkRun mapped = take_chunk(&retries, index, name, &clock);
      const fs::path& output = mapped.output;
      const std::string& note = mapped.note;
      // A seed without a model did not help either (recorded, as a
      // one-model drive's mapper run without a model is).
      if (output.empty()) {
        MapperAttempt attempt;
        attempt.matching_round = round.index;
        attempt.chunk = static_cast<int>(k);
        attempt.random_seed = seed;
        attempt.model_path = MapperOutput(run, "chunk_" + suffix).string();
        mapping.attempts.push_back(attempt);
        break;
      }
      std::vector<fs::path> candidate = outputs;
      candidate[k] = output;
      const ChunkCombination combination = CombineChunkModels(
          run, "mapper_attempts/chunks_" + suffix, candidate, own);
      // Chunk k's new model may keep none of its own images, and be the
      // only chunk with a model.
      if (combination.chunk_of_sub_model.empty()) {
        clock.Done(note + "; its model keeps none of the chunk's own images",
                   mapped.seconds);
        break;
      }
      // A model already chosen: one that cannot be calibrated is left out,
      // as an extra mapper run's failure is (RunExtraMapper).
      try {
        calibration = CalibrateCombination(run, round, combination);
      } catch (const FormatError& failure) {
        clock.Done(note + "; left out: " + failure.what(), mapped.seconds);
        break;
      }
      mapping.attempts.push_back(
          summarize(seed, combination, static_cast<int>(k)));
      const MapperAttempt& attempt = mapping.attempts.back();
      const MapperAttempt& best = mapping.attempts[mapping.chosen];
      const std::string pairs =
          std::to_string(attempt.num_pairs_used) + " of the drive's " +
          std::to_string(attempt.num_pairs) + " motion pairs used (was " +
          std::to_string(best.num_pairs_used) + ")";
      if (attempt.num_pairs_used <= best.num_pairs_used) {
        // The next seed is not tried either: where one seed did not help,
        // the fold is the scene's (measured on the rendered 1 000-image
        // drive: seeds 1 and 2 folded its turn close to a wall as seed 0
        // did, at 100 s each), as in a one-model drive whose seeds repeat
        // their contradictions (RepeatsContradictions).
        clock.Done(note + "; " + pairs + ": not better, no further seed",
                   mapped.seconds);
        break;
      }
      outputs = candidate;
      chosen = combination;
      mapping.chosen = static_cast<int>(mapping.attempts.size()) - 1;
      folded = FoldedPairsOfChunks(calibration, chosen, chunks.size());
      for (size_t j = k + 1; j < chunks.size(); ++j) {
        if (folded[j] == 0 && first_retry[j]) {
          retries.Cancel(*first_retry[j]);
          first_retry[j].reset();
        }
      }
      clock.Done(note + "; " + pairs + ": this model kept", mapped.seconds);
    }
  }
  progress->SetNumImages(static_cast<int>(images.size()));
  return mapping;
}

}  // namespace

std::vector<std::string> ReconstructionWorkspaceEntries() {
  return {"image_list.txt",
          kOdometryPairsFile,
          "database.db",
          "database_rematched.db",
          "logs",
          "stages",
          "commands.txt",
          "mapper_attempts",
          "stretches",
          "chunks",
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
  const Trajectory odometry = ReadOdometryOf(inputs);
  CheckOdometrySpeed(odometry);
  std::vector<TimedImage> images;
  FrameSpacing frame_spacing;
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
    frames.field_of_view_deg = RunFieldOfViewDeg(run);
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
              "); the sequential matcher needs that: use --matcher odometry");
        }
      }
    }
    std::ostringstream list;
    for (const TimedImage& image : selection.kept) list << image.name << "\n";
    WriteFileAtomically((workspace / "image_list.txt").string(), list.str());
    images = selection.kept;
    frame_spacing = selection.spacing;
    clock.Done("kept " + std::to_string(selection.kept.size()) + " of " +
               std::to_string(selection.num_images) + " images, " +
               FormatRounded(selection.spacing.min_translation_m) + " m or " +
               FormatRounded(selection.spacing.min_rotation_deg) +
               " deg apart (" + FormatRounded(frames.field_of_view_deg) +
               " deg field of view; " +
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
  result.frame_spacing = frame_spacing;
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
  progress.SetNumImages(static_cast<int>(images.size()));
  runner_options.on_output_line = [&progress](const std::string& line) {
    progress.ColmapLine(line);
  };
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

  // The pairs chosen from the odometry look at most half the camera's
  // horizontal field of view apart (fx is every COLMAP model's first
  // parameter).
  ReconstructionOptions tuned = run;
  const std::vector<ColmapDatabaseCamera> cameras =
      ReadColmapDatabaseCameras(database);
  if (cameras.size() == 1 && !cameras[0].camera.params.empty() &&
      cameras[0].camera.params[0] > 0.0) {
    const double fov_deg = FieldOfViewDeg(cameras[0].camera.params[0],
                                          0.5 * cameras[0].camera.width);
    tuned.candidate_pairs.max_view_angle_deg =
        ViewAngleLimitDeg(fov_deg, run.candidate_pairs.max_view_angle_deg);
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
  if (matcher == "odometry") {
    std::vector<Rigid3d> poses;
    std::vector<const TimedImage*> posed;
    InterpolationFailure why;
    for (const TimedImage& image : images) {
      const auto pose = InterpolateOdometry(
          odometry,
          image.stamp_ns + inputs.association.camera_time_offset_ns,
          OdometryGapLimitS(inputs.association.max_odometry_gap_s, odometry),
          &why);
      if (!pose) continue;
      poses.push_back(*pose);
      posed.push_back(&image);
    }
    const std::vector<std::pair<int, int>> pairs =
        OdometryCandidatePairs(poses, tuned.candidate_pairs);
    std::ostringstream list;
    for (const auto& [a, b] : pairs) {
      list << posed[a]->name << " " << posed[b]->name << "\n";
    }
    WriteFileAtomically((workspace / kOdometryPairsFile).string(), list.str());
    progress.Note(
        2,
        std::to_string(pairs.size()) +
            " image pairs chosen from the odometry (the " +
            std::to_string(tuned.candidate_pairs.min_neighbors_each_side) +
            " nearest images on each side, baselines up to " +
            FormatRounded(tuned.candidate_pairs.max_distance_m) +
            " m along the path within " +
            FormatRounded(tuned.candidate_pairs.max_view_angle_deg) +
            " deg of viewing direction, and loops)");
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
  // (mapper_policy.h). A drive longer than one chunk: chunk by chunk, a
  // chunk mapped again only where its model is folded (MapInChunks).
  const std::vector<MapperChunk> chunks =
      SplitIntoChunks(static_cast<int>(images.size()), run.chunks);
  std::vector<MapperAttempt> attempts;
  int chosen = -1;
  std::optional<std::string> contradiction_warning;
  std::string mapper_log = (workspace / "logs" / "mapper_seed_0.log").string();
  std::string mapper_runs;  // "3 runs", "any of the 2 chunks"
  if (chunks.size() > 1) {
    progress.Note(3,
                  std::to_string(images.size()) + " images: mapped in " +
                      std::to_string(chunks.size()) + " chunks of " +
                      std::to_string(chunks[0].last - chunks[0].first + 1) +
                      " sharing at least " +
                      std::to_string(run.chunks.overlap) + " images");
    const ChunkedMapping mapping =
        MapInChunks(&colmap, run, rounds[0], images, chunks, &progress);
    result.num_chunks = static_cast<int>(chunks.size());
    mapper_log = (workspace / "logs" / "mapper_chunk_0.log").string();
    mapper_runs = "any of the " + std::to_string(chunks.size()) + " chunks";
    attempts = mapping.attempts;
    chosen = mapping.chosen;
  } else {
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
    attempts = policy.attempts();
    chosen = policy.Best();
    contradiction_warning = policy.ContradictionWarning();
    mapper_runs = std::to_string(attempts.size()) +
                  (attempts.size() == 1 ? " run" : " runs");
  }
  if (chosen < 0) {
    throw ColmapError("COLMAP mapper produced no model in " + mapper_runs +
                      " (see " + mapper_log +
                      "): too little texture or overlap, or wrong intrinsics");
  }

  const MapperAttempt& best = attempts[chosen];
  std::vector<fs::path> stretch_models;
  if (run.map_unregistered_stretches) {
    stretch_models =
        MapUnregisteredStretches(&colmap,
                                 tuned,
                                 images,
                                 odometry,
                                 best,
                                 rounds.at(best.matching_round).database,
                                 &progress);
  }

  // [5] Calibration of the model the odometry contradicts least, with the
  // models of the stretches it left out.
  StageClock clock(&progress,
                   5,
                   "calibrating against the odometry (" +
                       (result.num_chunks > 0
                            ? "models of the " +
                                  std::to_string(result.num_chunks) + " chunks"
                            : "model of " + MapperAttemptName(best)) +
                       ")");
  const fs::path sparse = workspace / "sparse";
  ReplaceWithCopy(best.model_path, run.workspace_path, "sparse");
  // The stretch models become the next numbered sub-models.
  int next_sub_model = 0;
  for (const std::string& folder : FindColmapModelFolders(sparse.string())) {
    next_sub_model =
        std::max(next_sub_model,
                 SubModelNumber(fs::path(folder).filename().string()) + 1);
  }
  for (const fs::path& root : stretch_models) {
    for (const std::string& folder : FindColmapModelFolders(root.string())) {
      fs::copy(folder,
               sparse / std::to_string(next_sub_model++),
               fs::copy_options::recursive);
    }
  }
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
  if (contradiction_warning) {
    result.calibration.check.result.warnings.push_back(*contradiction_warning);
  }
  // At the clock offset the calibration used (estimated, or as given).
  AddImageCoverage(images,
                   result.calibration.systematics.camera_time_offset_ns,
                   &result.calibration);
  clock.Done("calibrated");
  return result;
}

}  // namespace odomcal
