// Stages, each reported to the progress callback: [1] frame selection
// (odometry), then the excitation check (excitation_precheck.h; a drive the
// odometry cannot calibrate stops here, before COLMAP, unless `force`), [2]
// feature extraction, [3] position priors + matching, [4] mapping, repeated
// with other random seeds while the odometry contradicts the model (see
// mapper_policy.h), [5] calibration. COLMAP runs headless on the CPU;
// intrinsics are kept fixed in the mapper when given, because
// self-calibration on robot video drifts.

#include "odomcal/plugin/colmap/reconstruction_pipeline.h"

#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/excitation_precheck.h"
#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/frame_selection.h"
#include "odomcal/adapters/image_timestamps.h"
#include "odomcal/adapters/input_plausibility.h"
#include "odomcal/plugin/colmap/image_coverage.h"
#include "odomcal/plugin/colmap/odometry_inputs.h"
#include "odomcal/plugin/colmap/reconstruction_stages.h"
#include "odomcal/plugin/output/output_file.h"
#include "odomcal/plugin/output/output_folder.h"
#include "odomcal/plugin/output/output_guard.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/format_number.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <sstream>

namespace odomcal {
namespace {

namespace fs = std::filesystem;
using reconstruction::Progress;
using reconstruction::StageClock;

bool IsImageExtension(const fs::path& path) {
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
    if (entry.is_regular_file() && IsImageExtension(entry.path())) {
      names.push_back(fs::relative(entry.path(), image_path).generic_string());
    }
  }
  std::sort(names.begin(), names.end());
  return names;
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

// A calibration of COLMAP's model refused for too little motion while the
// odometry at the same images turns enough (the pre-check said so): the
// model, not the drive, lacks the motion, and the refusal's advice ("drive
// turns in both directions") would send the user to the wrong place.
void SayWhenTheModelLostTheMotion(const ExcitationPrecheck& precheck,
                                  const CalibrationOptions& options,
                                  ReconstructionResult* result) {
  CalibrationResult& calibration = result->calibration.check.result;
  const CalibrationStatus status = calibration.status;
  if (!precheck.determinable ||
      (status != CalibrationStatus::kUnobservable &&
       status != CalibrationStatus::kNotEnoughMotion)) {
    return;
  }
  const CalibrationDiagnostics& odometry = precheck.verdict.diagnostics;
  const CalibrationDiagnostics& model = calibration.diagnostics;
  // Only where the model lost turns: half of them, or every turn of one
  // direction (a refusal for other reasons, e.g. noisier poses than the
  // noise model, is the calibration's to explain).
  const bool lost_direction =
      (odometry.num_left_turns > 0 && model.num_left_turns == 0) ||
      (odometry.num_right_turns > 0 && model.num_right_turns == 0);
  if (!lost_direction &&
      2 * model.num_rotating_pairs >= odometry.num_rotating_pairs) {
    return;
  }
  std::ostringstream text;
  text << "the odometry at the selected images turns enough ("
       << odometry.num_left_turns << " left and " << odometry.num_right_turns
       << " right turns above " << FormatNumber(options.min_rotation_deg)
       << " deg in " << precheck.association.pairs.size()
       << " motion pairs, before COLMAP), COLMAP's model does not ("
       << model.num_left_turns << " and " << model.num_right_turns << " in the "
       << model.num_pairs_in
       << " motion pairs it holds): the motion was lost in the reconstruction, "
          "not in the drive; look at the images' texture (too little, "
          "repetitive), the intrinsics and the mapper logs";
  calibration.message += "; but " + text.str();
  calibration.warnings.push_back(text.str());
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
  // EQUIRECTANGULAR has no focal length: the default thresholds.
  const auto indices = ColmapCameraModelPinholeIndices(*model);
  if (!indices) return kColmapDefaultFieldOfViewDeg;
  const size_t fy = indices->fy;
  const size_t cx = indices->cx;
  const size_t cy = indices->cy;
  if (params.size() <= cy ||
      !std::all_of(params.begin(), params.begin() + cy + 1, [](double p) {
        return p > 0.0 && std::isfinite(p);
      })) {
    return kColmapDefaultFieldOfViewDeg;
  }
  return std::min(FieldOfViewDeg(params[0], params[cx]),
                  FieldOfViewDeg(params[fy], params[cy]));
}

// [1]: the images of run.image_path with their capture times, and those the
// odometry keeps (moved or turned enough since the last kept one), listed
// in the workspace's image_list.txt.
FrameSelection SelectImages(const ReconstructionOptions& run,
                            const Trajectory& odometry,
                            Progress* progress) {
  const ColmapCalibrationInputs& inputs = run.project;
  const fs::path workspace(run.workspace_path);
  StageClock clock(progress, 1, "selecting frames with the odometry");
  const ImageTimestamps timestamps =
      inputs.image_timestamps_path.empty()
          ? ImageTimestamps::FromFileNames(inputs.file_name_time_unit)
          : ImageTimestamps::FromCsv(inputs.image_timestamps_path,
                                     inputs.image_time_unit);
  std::vector<std::string> names = ListImages(run.image_path);
  if (!run.image_sub_folder.empty()) {
    const std::string prefix = run.image_sub_folder + "/";
    names.erase(std::remove_if(names.begin(),
                               names.end(),
                               [&](const std::string& name) {
                                 return name.rfind(prefix, 0) != 0;
                               }),
                names.end());
  }
  if (names.empty()) {
    throw FormatError(
        (fs::path(run.image_path) / run.image_sub_folder).string() +
        ": no images (.png, .jpg, .jpeg, .bmp, .tif)");
  }
  std::vector<TimedImage> all;
  all.reserve(names.size());
  for (const std::string& name : names) {
    std::string why;
    const auto stamp = timestamps.Lookup(name, &why);
    if (!stamp) throw FormatError(run.image_path + "/" + name + ": " + why);
    all.push_back({name, *stamp});
  }
  if (inputs.image_timestamps_path.empty()) {
    std::vector<int64_t> stamps_ns;
    stamps_ns.reserve(all.size());
    for (const TimedImage& image : all) stamps_ns.push_back(image.stamp_ns);
    CheckImageTimesAreNotFrameNumbers(
        stamps_ns, run.image_path, timestamps.how_read());
  }
  FrameSelectionOptions frames = run.frames;
  frames.field_of_view_deg = RunFieldOfViewDeg(run);
  frames.max_odometry_gap_s = inputs.association.max_odometry_gap_s;
  frames.camera_time_offset_ns = inputs.association.camera_time_offset_ns;
  FrameSelection selection = SelectFrames(all, odometry, frames);
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
  return selection;
}

// [4]: mapping, each model checked against the odometry; when the random
// seeds do not help, [3] and [4] once more on new matches
// (mapper_policy.h). A drive longer than one chunk: chunk by chunk, a chunk
// mapped again only where its model is folded (MapInChunks).
struct Mapping {
  std::vector<reconstruction::MatchingRound> rounds;
  std::vector<MapperAttempt> attempts;
  int chosen = -1;
  int num_chunks = 0;
  std::optional<std::string> contradiction_warning;
};

Mapping MapImages(ColmapRunner* colmap,
                  const ReconstructionOptions& run,
                  const std::string& matcher,
                  const reconstruction::MatchingRound& first_round,
                  const std::vector<TimedImage>& images,
                  const Trajectory& odometry,
                  MapperPolicy* policy,
                  Progress* progress) {
  const fs::path workspace(run.workspace_path);
  const std::string& database = first_round.database;
  Mapping mapping;
  mapping.rounds = {first_round};
  const std::vector<MapperChunk> chunks =
      SplitIntoChunks(static_cast<int>(images.size()), run.chunks);
  std::string mapper_log = (workspace / "logs" / "mapper_seed_0.log").string();
  std::string mapper_runs;  // "3 runs", "any of the 2 chunks"
  // What the initialisation ladder tried, where a run gave no model.
  std::string tried;
  reconstruction::MapperStart start;
  if (chunks.size() > 1) {
    progress->Note(3,
                   std::to_string(images.size()) + " images: mapped in " +
                       std::to_string(chunks.size()) + " chunks of " +
                       std::to_string(chunks[0].last - chunks[0].first + 1) +
                       " sharing at least " +
                       std::to_string(run.chunks.overlap) + " images");
    const reconstruction::ChunkedMapping chunked = reconstruction::MapInChunks(
        colmap, run, first_round, images, odometry, chunks, progress);
    mapping.num_chunks = static_cast<int>(chunks.size());
    mapper_log = (workspace / "logs" / "mapper_chunk_0.log").string();
    mapper_runs = "any of the " + std::to_string(chunks.size()) + " chunks";
    mapping.attempts = chunked.attempts;
    mapping.chosen = chunked.chosen;
    mapping.attempts.insert(mapping.attempts.end(),
                            chunked.initialization_attempts.begin(),
                            chunked.initialization_attempts.end());
    for (const std::string& summary : chunked.initialization_summaries) {
      tried += (tried.empty() ? "" : "; ") + summary;
    }
  } else {
    for (MapperStep step = policy->Next(); step.kind != MapperStep::Kind::kDone;
         step = policy->Next()) {
      if (step.kind == MapperStep::Kind::kMatchAgain) {
        reconstruction::MatchingRound again;
        again.index = step.matching_round;
        again.database = (workspace / "database_rematched.db").string();
        reconstruction::MatchAgain(
            colmap, matcher, again, database, run, progress);
        mapping.rounds.push_back(again);
        policy->MatchedAgain();
        continue;
      }
      reconstruction::MapWithSeed(colmap,
                                  run,
                                  mapping.rounds.at(step.matching_round),
                                  images,
                                  odometry,
                                  step.random_seed,
                                  progress,
                                  &start,
                                  policy);
    }
    mapping.attempts = policy->attempts();
    mapping.attempts.insert(
        mapping.attempts.end(), start.attempts.begin(), start.attempts.end());
    tried = start.summary;
    mapping.chosen = policy->Best();
    mapping.contradiction_warning = policy->ContradictionWarning();
    mapper_runs = std::to_string(mapping.attempts.size()) +
                  (mapping.attempts.size() == 1 ? " run" : " runs");
  }
  if (mapping.chosen < 0) {
    // The cause COLMAP's log gives: an initialisation that no pair passed
    // points at the images' overlap and motion, not at the intrinsics.
    const std::string cause = MapperFailureCause(mapper_log);
    throw ColmapError(
        "COLMAP mapper produced no model in " + mapper_runs +
        (tried.empty() ? "" : " (tried: " + tried + ")") + " (see " +
        mapper_log + ")" + (cause.empty() ? "" : ": " + cause) +
        (cause.find("initial") != std::string::npos
             ? ""
             : "; too little texture or overlap, or wrong intrinsics"));
  }
  return mapping;
}

// [5]: the chosen model copied to sparse/ with the stretch models as its
// next numbered sub-models, and calibrated there, so that every path in the
// outputs names sparse/, the model a later `odomcal colmap` would read.
void CalibrateChosenModel(const ReconstructionOptions& run,
                          const ColmapVersion& colmap_version,
                          const Mapping& mapping,
                          const std::vector<fs::path>& stretch_models,
                          const std::vector<TimedImage>& images,
                          Progress* progress,
                          ReconstructionResult* result) {
  const MapperAttempt& best = mapping.attempts[mapping.chosen];
  const fs::path workspace(run.workspace_path);
  StageClock clock(progress,
                   5,
                   "calibrating against the odometry (" +
                       (mapping.num_chunks > 0
                            ? "models of the " +
                                  std::to_string(mapping.num_chunks) + " chunks"
                            : "model of " + MapperAttemptName(best)) +
                       ")");
  const fs::path sparse = workspace / "sparse";
  reconstruction::ReplaceWithCopy(
      best.model_path, run.workspace_path, "sparse");
  int next_sub_model = 0;
  for (const std::string& folder : FindColmapModelFolders(sparse.string())) {
    next_sub_model = std::max(
        next_sub_model,
        reconstruction::SubModelNumber(fs::path(folder).filename().string()) +
            1);
  }
  for (const fs::path& root : stretch_models) {
    for (const std::string& folder : FindColmapModelFolders(root.string())) {
      fs::copy(folder,
               sparse / std::to_string(next_sub_model++),
               fs::copy_options::recursive);
    }
  }
  ColmapCalibrationInputs final_inputs = run.project;
  final_inputs.model_path = sparse.string();
  final_inputs.database_path = mapping.rounds.at(best.matching_round).database;
  result->model_path = final_inputs.model_path;
  result->database_path = final_inputs.database_path;
  result->calibration = CalibrateColmapProject(
      final_inputs, [progress, &clock](const std::string& message) {
        progress->Send(PipelineProgress::Event::kStageProgress,
                       5,
                       message,
                       clock.Seconds());
      });
  result->calibration.mapper_attempts = mapping.attempts;
  result->calibration.chosen_mapper_attempt = mapping.chosen;
  result->calibration.colmap_version = colmap_version.ToString();
  result->calibration.colmap_mapper =
      run.mapper_kind == MapperKind::kIncremental            ? "mapper"
      : reconstruction::GlobalMapperIsGlomap(colmap_version) ? "glomap mapper"
                                                             : "global_mapper";
  if (mapping.contradiction_warning) {
    result->calibration.check.result.warnings.push_back(
        *mapping.contradiction_warning);
  }
  // At the clock offset the calibration used (estimated, or as given).
  AddImageCoverage(images,
                   result->calibration.systematics.camera_time_offset_ns,
                   &result->calibration);
  clock.Done("calibrated");
}

// `run` as the mapper it asks for can take it with this COLMAP: global
// mapping maps the drive as one model (no chunks), and the standalone
// glomap has no random seed to vary.
ReconstructionOptions WithMapperOf(const ReconstructionOptions& run,
                                   const ColmapVersion& version,
                                   size_t num_images,
                                   Progress* progress) {
  ReconstructionOptions mapped = run;
  if (run.mapper_kind != MapperKind::kGlobal) return mapped;
  const bool glomap = reconstruction::GlobalMapperIsGlomap(version);
  std::string note =
      glomap ? "GLOMAP (" + run.glomap_path + ") maps the images: COLMAP " +
                   version.ToString() + " has no global_mapper (from 4.0)"
             : "COLMAP's global_mapper maps the images";
  if (run.chunks.max_images > 0 &&
      num_images > static_cast<size_t>(run.chunks.max_images)) {
    note += "; all " + std::to_string(num_images) +
            " in one model (global mapping has no chunks)";
  }
  mapped.chunks.max_images = 0;
  if (glomap && run.mapper.max_seeds > 1) {
    note += "; one mapper attempt (glomap has no random seed)";
    mapped.mapper.max_seeds = 1;
  }
  progress->Note(1, note);
  return mapped;
}

}  // namespace

bool IsImageFile(const std::filesystem::path& path) {
  return IsImageExtension(path);
}

std::vector<FlaggedPath> UserInputs(const ReconstructionOptions& run) {
  std::vector<FlaggedPath> inputs = {
      {run.image_path, "--image_path"},
      {run.project.odometry_path, "--odometry"},
      {run.project.image_timestamps_path, "--image_timestamps"}};
  if (run.extracted_inputs_path.empty()) return inputs;
  const fs::path extracted =
      fs::path(run.extracted_inputs_path).lexically_normal();
  inputs.erase(std::remove_if(inputs.begin(),
                              inputs.end(),
                              [&extracted](const FlaggedPath& input) {
                                const fs::path relative =
                                    fs::path(input.path)
                                        .lexically_normal()
                                        .lexically_relative(extracted);
                                return !relative.empty() &&
                                       *relative.begin() != "..";
                              }),
               inputs.end());
  return inputs;
}

const char* ToString(MapperKind kind) {
  return kind == MapperKind::kGlobal ? "global" : "incremental";
}

std::vector<std::string> ReconstructionWorkspaceEntries() {
  return {"bag_inputs",
          "image_list.txt",
          reconstruction::kOdometryPairsFile,
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
  run.mapper.Check();  // before any file is touched
  Progress progress(callback);
  const fs::path workspace(run.workspace_path);
  // Reruns reuse the workspace: odomcal's own entries in it are replaced.
  GuardedPaths guarded;
  guarded.inputs = UserInputs(run);
  guarded.output_folders = {{run.workspace_path, "--workspace_path"}};
  CheckOutputsApartFromInputs(guarded);
  ClaimOutputFolder(run.workspace_path,
                    ReconstructionWorkspaceEntries(),
                    ExistingOutputs::kReplaceOwn);

  const Trajectory odometry = ReadOdometryOf(inputs);
  CheckOdometrySpeed(odometry);
  const FrameSelection selection = SelectImages(run, odometry, &progress);
  const std::vector<TimedImage>& images = selection.kept;

  // Before COLMAP: whether the odometry between the image times can
  // determine the calibration at all (excitation_precheck.h).
  std::vector<int64_t> image_stamps;
  image_stamps.reserve(images.size());
  for (const TimedImage& image : images) image_stamps.push_back(image.stamp_ns);
  const ExcitationPrecheck precheck = PrecheckExcitation(image_stamps,
                                                         odometry,
                                                         inputs.association,
                                                         inputs.calibration,
                                                         inputs.systematics);
  progress.Note(1, ExcitationLine(precheck, inputs.calibration, run.force));
  ReconstructionResult result;
  result.frame_spacing = selection.spacing;
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
  runner_options.glomap_executable = run.glomap_path;
  ColmapRunner colmap(runner_options);
  progress.Note(1,
                "COLMAP " + colmap.Version().ToString() + " (" +
                    run.colmap_path + "): its option names are passed");
  const ReconstructionOptions mapped =
      WithMapperOf(run, colmap.Version(), images.size(), &progress);
  MapperPolicy policy(mapped.mapper);

  reconstruction::MatchingRound first_round;
  first_round.database = (workspace / "database.db").string();
  reconstruction::ExtractFeatures(
      &colmap, mapped, images.size(), first_round.database, &progress);
  const ReconstructionOptions tuned =
      reconstruction::TuneCandidatePairs(mapped, first_round.database);
  const std::string matcher = reconstruction::MatchImages(
      &colmap, mapped, tuned, images, odometry, first_round, &progress);
  const Mapping mapping = MapImages(&colmap,
                                    mapped,
                                    matcher,
                                    first_round,
                                    images,
                                    odometry,
                                    &policy,
                                    &progress);
  result.num_chunks = mapping.num_chunks;

  std::vector<fs::path> stretch_models;
  if (mapped.map_unregistered_stretches) {
    const MapperAttempt& best = mapping.attempts[mapping.chosen];
    stretch_models = reconstruction::MapUnregisteredStretches(
        &colmap,
        tuned,
        images,
        odometry,
        best,
        mapping.rounds.at(best.matching_round).database,
        &progress);
  }
  // [5] Calibration of the model the odometry contradicts least, with the
  // models of the stretches it left out.
  CalibrateChosenModel(mapped,
                       colmap.Version(),
                       mapping,
                       stretch_models,
                       images,
                       &progress,
                       &result);
  SayWhenTheModelLostTheMotion(precheck, inputs.calibration, &result);
  return result;
}

}  // namespace odomcal
