// [4] the mapper's initialisation ladder of the reconstruction pipeline
// (reconstruction_stages.h, mapper_initialization.h): what is mapped when
// COLMAP's own initial pair search gave no model.
#include "odomcal/adapters/association.h"
#include "odomcal/adapters/colmap_database.h"
#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/colmap_two_view_geometries.h"
#include "odomcal/adapters/format_error.h"
#include "odomcal/plugin/colmap/reconstruction_stages.h"
#include "odomcal/plugin/output/output_file.h"

#include <filesystem>
#include <map>
#include <sstream>

namespace odomcal::reconstruction {

namespace fs = std::filesystem;

namespace {

// `images` with their database ids and the odometry at their times; images
// the database does not hold are left out.
std::vector<InitialPairImage> InitialPairImages(
    const ReconstructionOptions& run,
    const std::string& database,
    const Trajectory& odometry,
    const std::vector<TimedImage>& images) {
  std::map<std::string, uint32_t> ids;
  for (const ColmapDatabaseImage& image : ReadColmapDatabaseImages(database)) {
    ids[image.name] = image.image_id;
  }
  const AssociationOptions& association = run.project.association;
  const double max_gap_s =
      OdometryGapLimitS(association.max_odometry_gap_s, odometry);
  std::vector<InitialPairImage> result;
  for (const TimedImage& image : images) {
    const auto id = ids.find(image.name);
    if (id == ids.end()) continue;
    InitialPairImage entry;
    entry.image_id = id->second;
    entry.name = image.name;
    entry.origin_from_odom =
        InterpolateOdometry(odometry,
                            image.stamp_ns + association.camera_time_offset_ns,
                            max_gap_s,
                            nullptr);
    result.push_back(std::move(entry));
  }
  return result;
}

int NumRegisteredImages(const fs::path& output) {
  int count = 0;
  for (const std::string& folder : FindColmapModelFolders(output.string())) {
    count += static_cast<int>(ReadColmapModel(folder).images.size());
  }
  return count;
}

std::string LogOf(const ReconstructionOptions& run, const std::string& entry) {
  return (fs::path(run.workspace_path) / "logs" / ("mapper_" + entry + ".log"))
      .string();
}

}  // namespace

InitializationClimb ClimbInitializationLadder(ColmapRunner* colmap,
                                              const ReconstructionOptions& run,
                                              const MatchingRound& round,
                                              const Trajectory& odometry,
                                              const LadderImages& images,
                                              const std::string& entry,
                                              int seed,
                                              int chunk,
                                              int num_threads,
                                              Progress* progress) {
  InitializationClimb climb;
  climb.first.matching_round = round.index;
  climb.first.chunk = chunk;
  climb.first.random_seed = seed;
  climb.first.model_path = MapperOutput(run, entry).string();
  climb.first.failure_cause = MapperFailureCause(LogOf(run, entry));

  std::vector<InitialPairCandidate> default_pairs;
  std::vector<InitialPairCandidate> relaxed_pairs;
  try {
    const std::vector<InitialPairImage> candidates =
        InitialPairImages(run, round.database, odometry, images.mapped);
    const std::vector<ColmapVerifiedPair> verified = ReadColmapVerifiedPairs(
        round.database, RelaxedInitialization::kMinNumInliers);
    default_pairs = RankInitialPairs(candidates, verified, InitialPairTests());
    InitialPairTests relaxed;
    relaxed.min_inliers = RelaxedInitialization::kMinNumInliers;
    relaxed.max_forward_motion = RelaxedInitialization::kMaxForwardMotion;
    relaxed_pairs = RankInitialPairs(candidates, verified, relaxed);
  } catch (const FormatError& failure) {
    // Without the verified pairs, COLMAP's own search with relaxed tests
    // is still worth a run.
    progress->Note(4,
                   std::string("    no initial pair from the odometry: ") +
                       failure.what());
  }
  const std::vector<MapperInitialization> ladder = InitializationLadder(
      default_pairs, relaxed_pairs, !images.window.empty());
  for (size_t k = 0; k < ladder.size(); ++k) {
    const MapperInitialization& rung = ladder[k];
    const std::string name = entry + "_init_" + std::to_string(k + 1);
    fs::path list = images.image_list;
    if (rung.kind == MapperInitialization::Kind::kNeighbourWindow) {
      std::ostringstream text;
      for (const TimedImage& image : images.window) text << image.name << "\n";
      list = fs::path(run.workspace_path) / "chunks" / (name + "_images.txt");
      WriteFileAtomically(list.string(), text.str());
    }
    std::vector<std::string> arguments =
        MapperArguments(run,
                        colmap->Version(),
                        round.database,
                        MapperOutput(run, name),
                        list,
                        seed,
                        num_threads);
    const std::vector<std::string> initialization = rung.MapperArguments();
    arguments.insert(
        arguments.end(), initialization.begin(), initialization.end());
    StageClock clock(progress,
                     4,
                     "COLMAP mapping " + images.what + " again (" +
                         std::to_string(k + 1) + " of " +
                         std::to_string(ladder.size()) +
                         " ways to start): " + rung.Describe());
    const std::optional<ColmapStageResult> result =
        RunExtraMapper(colmap, run, name, arguments, &clock);
    MapperAttempt attempt;
    attempt.matching_round = round.index;
    attempt.chunk = chunk;
    attempt.random_seed = seed;
    attempt.model_path = MapperOutput(run, name).string();
    attempt.initialization = ToString(rung.kind);
    if (rung.pair) attempt.initial_pair = {rung.pair->name1, rung.pair->name2};
    if (!result) {
      attempt.failure_cause = MapperFailureCause(LogOf(run, name));
      climb.rungs.push_back(attempt);
      continue;
    }
    attempt.produced_model = true;
    attempt.num_registered_images =
        NumRegisteredImages(MapperOutput(run, name));
    climb.rungs.push_back(attempt);
    clock.Done(Note(*result) + "; " +
               std::to_string(attempt.num_registered_images) +
               " images registered");
    climb.used = rung;
    climb.output = MapperOutput(run, name);
    break;
  }
  return climb;
}

std::string DescribeClimb(const InitializationClimb& climb) {
  int odometry_pairs = 0;
  for (const MapperAttempt& attempt : climb.rungs) {
    odometry_pairs += attempt.initialization == "odometry_pair" ? 1 : 0;
  }
  std::string text = "COLMAP's initial pair search";
  if (odometry_pairs > 0) {
    text += ", " + std::to_string(odometry_pairs) +
            " initial pair(s) chosen from the odometry";
  }
  text += ", relaxed initialisation tests";
  for (const MapperAttempt& attempt : climb.rungs) {
    if (attempt.initialization == "neighbour_window") {
      text += ", the chunk with its neighbours' images";
    }
  }
  return text;
}

}  // namespace odomcal::reconstruction
