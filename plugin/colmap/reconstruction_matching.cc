// [2] feature extraction and [3] matching of the reconstruction pipeline
// (reconstruction_stages.h).
#include "odomcal/adapters/colmap_database.h"
#include "odomcal/adapters/colmap_database_order.h"
#include "odomcal/adapters/colmap_database_priors.h"
#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/input_plausibility.h"
#include "odomcal/adapters/text_reader.h"
#include "odomcal/plugin/colmap/mapper_stretches.h"
#include "odomcal/plugin/colmap/reconstruction_stages.h"
#include "odomcal/plugin/output/output_file.h"
#include "odomcal/solver/format_number.h"

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace odomcal::reconstruction {

namespace fs = std::filesystem;

namespace {

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

}  // namespace

std::vector<std::string> MatcherArguments(const std::string& matcher,
                                          const MatchingRound& round,
                                          const ReconstructionOptions& run,
                                          const ColmapVersion& version) {
  const ColmapOptionNames names = ColmapOptionNamesFor(version);
  std::vector<std::string> arguments = {
      matcher == "odometry" ? "matches_importer" : matcher + "_matcher",
      "--database_path",
      round.database,
      "--" + names.matching_use_gpu,
      "0",
      "--" + names.matching_num_threads,
      std::to_string(run.num_threads)};
  if (matcher == "odometry") {
    arguments.insert(
        arguments.end(),
        {"--match_list_path",
         (fs::path(run.workspace_path) / kOdometryPairsFile).string(),
         "--match_type",
         "pairs"});
  } else if (matcher == "spatial") {
    // 3.10 replaced is_gps by each prior's coordinate system (the priors
    // odomcal writes say CARTESIAN; colmap_database_priors.h).
    if (!version.AtLeast(3, 10)) {
      arguments.insert(arguments.end(), {"--SpatialMatching.is_gps", "0"});
    }
    arguments.insert(arguments.end(),
                     {"--SpatialMatching.ignore_z",
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

std::vector<std::string> FeatureExtractorArguments(
    const ReconstructionOptions& run,
    const ColmapVersion& version,
    const std::string& database) {
  const fs::path workspace(run.workspace_path);
  const ColmapOptionNames names = ColmapOptionNamesFor(version);
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
      "--" + names.extraction_use_gpu,
      "0",
      "--" + names.extraction_max_num_features,
      std::to_string(run.max_num_features),
      "--" + names.extraction_num_threads,
      std::to_string(run.num_threads)};
  if (!run.camera_params.empty()) {
    arguments.insert(arguments.end(),
                     {"--ImageReader.camera_params", run.camera_params});
  }
  return arguments;
}

void ExtractFeatures(ColmapRunner* colmap,
                     const ReconstructionOptions& run,
                     size_t num_images,
                     const std::string& database,
                     Progress* progress) {
  const fs::path workspace(run.workspace_path);
  StageClock clock(progress, 2, "COLMAP feature extraction");
  const std::vector<std::string> arguments =
      FeatureExtractorArguments(run, colmap->Version(), database);
  const ColmapStageResult stage =
      colmap->RunStage("feature_extractor", arguments, {database});
  CheckImagesWereRead(database,
                      num_images,
                      run.image_path,
                      stage.log_path,
                      workspace / "stages" / "feature_extractor.done");
  // The same images get the same ids on every run (colmap_database_order.h).
  std::string order;
  try {
    if (RenumberColmapImagesByName(database)) {
      order = "; image ids set in name order";
    }
  } catch (const FormatError& failure) {
    order =
        std::string("; image ids left in extraction order: ") + failure.what();
  }
  clock.Done(Note(stage) + order);
}

// The pairs chosen from the odometry look at most half the camera's
// horizontal field of view apart (fx is the first parameter of every COLMAP
// model that has a focal length; EQUIRECTANGULAR has none).
ReconstructionOptions TuneCandidatePairs(const ReconstructionOptions& run,
                                         const std::string& database) {
  ReconstructionOptions tuned = run;
  const std::vector<ColmapDatabaseCamera> cameras =
      ReadColmapDatabaseCameras(database);
  if (cameras.size() == 1 &&
      ColmapCameraModelPinholeIndices(cameras[0].camera.model) &&
      cameras[0].camera.params[0] > 0.0) {
    const double fov_deg = FieldOfViewDeg(cameras[0].camera.params[0],
                                          0.5 * cameras[0].camera.width);
    tuned.candidate_pairs.max_view_angle_deg =
        ViewAngleLimitDeg(fov_deg, run.candidate_pairs.max_view_angle_deg);
  }
  return tuned;
}

std::string MatchImages(ColmapRunner* colmap,
                        const ReconstructionOptions& run,
                        const ReconstructionOptions& tuned,
                        const std::vector<TimedImage>& images,
                        const Trajectory& odometry,
                        const MatchingRound& round,
                        Progress* progress) {
  const ColmapCalibrationInputs& inputs = run.project;
  const fs::path workspace(run.workspace_path);
  const ColmapVersion& version = colmap->Version();
  const std::string& database = round.database;
  const std::string& matcher = run.matcher;
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
    progress->Note(
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
  StageClock clock(progress, 3, "COLMAP " + matcher + " matching");
  clock.Done(
      Note(colmap->RunStage(matcher + "_matcher",
                            MatcherArguments(matcher, round, run, version),
                            {database})));
  return matcher;
}

}  // namespace odomcal::reconstruction
