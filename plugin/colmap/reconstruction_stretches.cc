// [4] for the stretches of images the chosen model left unregistered
// (reconstruction_stages.h): each matched along the odometry and mapped on
// its own.
#include "odomcal/adapters/colmap_database.h"
#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/input_plausibility.h"
#include "odomcal/plugin/colmap/image_coverage.h"
#include "odomcal/plugin/colmap/mapper_stretches.h"
#include "odomcal/plugin/colmap/reconstruction_stages.h"
#include "odomcal/plugin/output/output_file.h"

#include <cstdint>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

namespace odomcal::reconstruction {

namespace fs = std::filesystem;

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
  const ColmapCalibrationRun calibrated = CalibrateColmapProject(
      CheckCalibrationInputs(run, best.model_path, database));
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
  const ColmapOptionNames names = ColmapOptionNamesFor(colmap->Version());
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
                                          "--" + names.matching_use_gpu,
                                          "0",
                                          "--" + names.matching_num_threads,
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
      std::vector<std::string> arguments = MapperArguments(run,
                                                           colmap->Version(),
                                                           database,
                                                           output,
                                                           list_path,
                                                           std::nullopt,
                                                           run.num_threads);
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

}  // namespace odomcal::reconstruction
