// The stages of ReconstructAndCalibrate (reconstruction_pipeline.h), shared
// by the files that implement them: progress and stage clocks
// (reconstruction_progress.h), matching (reconstruction_matching.cc), mapper
// runs (reconstruction_mapper.cc), stretches the chosen model left out
// (reconstruction_stretches.cc), chunked mapping (reconstruction_chunks.cc)
// and chunk folds posed from the odometry (reconstruction_chunk_folds.cc).
// Internal: not installed.
#pragma once

#include "odomcal/adapters/image_timestamps.h"
#include "odomcal/adapters/trajectory.h"
#include "odomcal/plugin/colmap/colmap_calibration.h"
#include "odomcal/plugin/colmap/colmap_runner.h"
#include "odomcal/plugin/colmap/mapper_attempts.h"
#include "odomcal/plugin/colmap/mapper_chunks.h"
#include "odomcal/plugin/colmap/mapper_initialization.h"
#include "odomcal/plugin/colmap/mapper_policy.h"
#include "odomcal/plugin/colmap/reconstruction_pipeline.h"
#include "odomcal/plugin/colmap/reconstruction_progress.h"

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace odomcal::reconstruction {

// One matching of the images and the mapper runs on it.
struct MatchingRound {
  int index = 0;  // MapperAttempt::matching_round
  std::string database;
};

// The inputs of a calibration that checks a model between the stages
// (mapper attempts, chunk combinations, stretches left out): run.project on
// `model_path` and `database`, without the joint adjustment. The checks read
// the two-step result; the adjustment, whose cost grows with the drive, runs
// once, in the final calibration.
ColmapCalibrationInputs CheckCalibrationInputs(const ReconstructionOptions& run,
                                               const std::string& model_path,
                                               const std::string& database);

// --matcher odometry: the pairs chosen from the odometry
// (OdometryCandidatePairs), one "name1 name2" per line.
inline constexpr const char* kOdometryPairsFile = "odometry_pairs.txt";

// `colmap feature_extractor` arguments for the COLMAP `version`.
std::vector<std::string> FeatureExtractorArguments(
    const ReconstructionOptions& run,
    const ColmapVersion& version,
    const std::string& database);

// [2]: `colmap feature_extractor` on the selected images (the list in the
// workspace's image_list.txt), intrinsics given or estimated.
void ExtractFeatures(ColmapRunner* colmap,
                     const ReconstructionOptions& run,
                     size_t num_images,
                     const std::string& database,
                     Progress* progress);

// The run's options with the odometry pairs' viewing-angle limit set from
// the camera COLMAP extracted the features with.
ReconstructionOptions TuneCandidatePairs(const ReconstructionOptions& run,
                                         const std::string& database);

// [3]: the first matching of `round` (its database holds the features),
// guided by the odometry positions; returns the matcher that ran.
std::string MatchImages(ColmapRunner* colmap,
                        const ReconstructionOptions& run,
                        const ReconstructionOptions& tuned,
                        const std::vector<TimedImage>& images,
                        const Trajectory& odometry,
                        const MatchingRound& round,
                        Progress* progress);

// `colmap <matcher>` arguments of `round` for the COLMAP `version`.
std::vector<std::string> MatcherArguments(const std::string& matcher,
                                          const MatchingRound& round,
                                          const ReconstructionOptions& run,
                                          const ColmapVersion& version);

// [3] again: the features of `first_database` in round.database, matched
// anew with the same settings (COLMAP's two-view verification is random, so
// the matches differ).
void MatchAgain(ColmapRunner* colmap,
                const std::string& matcher,
                const MatchingRound& round,
                const std::string& first_database,
                const ReconstructionOptions& run,
                Progress* progress);

// Where `colmap mapper` run as stage "mapper_<entry>" writes its
// sub-models: mapper_attempts/<entry> in the workspace.
std::filesystem::path MapperOutput(const ReconstructionOptions& run,
                                   const std::string& entry);

// `colmap mapper` on `database`'s matches of the images in `image_list`,
// with the intrinsics kept fixed when given (--camera_params), and the
// random seed when `random_seed` holds one, in the option names of
// `version` (ColmapOptionNamesFor).
std::vector<std::string> MapperArguments(
    const ReconstructionOptions& run,
    const ColmapVersion& version,
    const std::string& database,
    const std::filesystem::path& output,
    const std::filesystem::path& image_list,
    std::optional<int> random_seed,
    int num_threads);

// The main mapping of run.mapper_kind == kGlobal: `colmap global_mapper`
// from COLMAP 4.0 (its GlobalMapper.* options), else `glomap mapper`, which
// maps every image of `database` (odomcal's database holds just the selected
// images) and has no random seed. Intrinsics kept fixed when given.
struct MapperCommand {
  ColmapProgram program = ColmapProgram::kColmap;
  std::vector<std::string> arguments;
};
MapperCommand GlobalMapperCommand(const ReconstructionOptions& run,
                                  const ColmapVersion& version,
                                  const std::string& database,
                                  const std::filesystem::path& output,
                                  const std::filesystem::path& image_list,
                                  std::optional<int> random_seed,
                                  int num_threads);

// Whether kGlobal runs the standalone glomap with this COLMAP.
bool GlobalMapperIsGlomap(const ColmapVersion& version);

// Starts `arguments` as stage "mapper_<entry>" into MapperOutput(run,
// entry), its output folder emptied first unless the stage is reused.
RunningStage StartMapper(ColmapRunner* colmap,
                         const ReconstructionOptions& run,
                         const std::string& entry,
                         const std::vector<std::string>& arguments,
                         ColmapProgram program = ColmapProgram::kColmap);

// The end of a mapper run for a model beside the main one (a stretch, a
// chunk): nothing when COLMAP failed or gave no model (`clock`'s stage then
// ends saying so), and the run goes on without it.
std::optional<ColmapStageResult> FinishExtraMapper(
    RunningStage* stage,
    const ReconstructionOptions& run,
    const std::string& entry,
    StageClock* clock);

// An extra mapper run (FinishExtraMapper), started and waited for.
std::optional<ColmapStageResult> RunExtraMapper(
    ColmapRunner* colmap,
    const ReconstructionOptions& run,
    const std::string& entry,
    const std::vector<std::string>& arguments,
    StageClock* clock);

// How the mapper of a drive of one model starts, and what the ladder tried.
struct MapperStart {
  // The ladder's rung that gave a model: later seeds start the same way.
  std::optional<MapperInitialization> initialization;
  bool climbed = false;                 // the ladder ran (once per drive)
  std::vector<MapperAttempt> attempts;  // InitializationClimb::tried
  std::string summary;                  // DescribeClimb
};

// [4]: `colmap mapper` with `seed` on the round's matches, its model
// calibrated and recorded in `policy`. The first incremental run that gives
// no model while no earlier run gave one climbs the initialisation ladder
// (ClimbInitializationLadder); `start` keeps what it found.
void MapWithSeed(ColmapRunner* colmap,
                 const ReconstructionOptions& run,
                 const MatchingRound& round,
                 const std::vector<TimedImage>& images,
                 const Trajectory& odometry,
                 int seed,
                 Progress* progress,
                 MapperStart* start,
                 MapperPolicy* policy);

// The images of a mapper run that gave no model, for the ladder below:
// those it mapped (listed in `image_list`), and, for a chunk, the chunk
// with its neighbours' images (empty: not a chunk); `what` names them in
// progress lines ("the drive", "chunk 2").
struct LadderImages {
  std::vector<TimedImage> mapped;
  std::filesystem::path image_list;
  std::vector<TimedImage> window;
  std::string what;
};

// What the ladder tried and found.
struct InitializationClimb {
  // The run that gave no model (COLMAP's own search), with its cause.
  MapperAttempt first;
  std::vector<MapperAttempt> rungs;          // each rung run, in order
  std::optional<MapperInitialization> used;  // the rung that gave a model
  std::filesystem::path output;  // its mapper output; empty: none did
};

// [4] after `colmap mapper` as stage "mapper_<entry>" gave no model (an
// incremental mapper run): InitializationLadder's rungs
// (mapper_initialization.h), each a mapper run with `seed` into
// mapper_attempts/<entry>_init_<k>, until one gives a model. `chunk`: the
// chunk's index for the records, -1 for a drive of one model.
InitializationClimb ClimbInitializationLadder(ColmapRunner* colmap,
                                              const ReconstructionOptions& run,
                                              const MatchingRound& round,
                                              const Trajectory& odometry,
                                              const LadderImages& images,
                                              const std::string& entry,
                                              int seed,
                                              int chunk,
                                              int num_threads,
                                              Progress* progress);

// "COLMAP's initial pair search, 3 initial pair(s) chosen from the
// odometry, relaxed initialisation tests, ..." for an error message.
std::string DescribeClimb(const InitializationClimb& climb);

// `workspace`/`entry` becomes a copy of folder `source`; a failure leaves no
// half copy under that name.
void ReplaceWithCopy(const std::filesystem::path& source,
                     const std::string& workspace,
                     const std::string& entry);

// The number a sub-model folder is named by ("0", "1", ...); -1 for any
// other name.
int SubModelNumber(const std::string& name);

// "images 86-300".
std::string ImageRange(int first, int last);

// [4] for the stretches of at least kMinStretchModelImages images the
// chosen model left unregistered, each matched along the odometry and
// mapped on its own; the mapper output folders with a model.
std::vector<std::filesystem::path> MapUnregisteredStretches(
    ColmapRunner* colmap,
    const ReconstructionOptions& run,
    const std::vector<TimedImage>& images,
    const Trajectory& odometry,
    const MapperAttempt& best,
    const std::string& database,
    Progress* progress);

// A combination of chunk models: mapper_attempts/<entry>, its numbered
// sub-models, and the chunk each came from.
struct ChunkCombination {
  std::string entry;
  std::vector<int> chunk_of_sub_model;
};

// Chunk k's sub-models in `chosen` with a stretch left out as folded posed
// again from the odometry, triangulated and adjusted by COLMAP, written as
// chunk k's model mapper_attempts/<entry>; the number posed again (0: none
// could be, `why` says why).
int PoseChunkFoldsFromOdometry(ColmapRunner* colmap,
                               const ReconstructionOptions& run,
                               const MatchingRound& round,
                               const ColmapCalibrationRun& calibration,
                               const ChunkCombination& chosen,
                               size_t k,
                               const std::string& entry,
                               std::string* why);

struct ChunkedMapping {
  std::vector<MapperAttempt> attempts;  // all chunks, then each chunk again
  int chosen = -1;                      // -1: no chunk gave a model
  // The runs of chunks that gave no model at first and the ladder's runs
  // (ClimbInitializationLadder), and what it tried on each chunk that still
  // gave none, for the records and messages.
  std::vector<MapperAttempt> initialization_attempts;
  std::vector<std::string> initialization_summaries;
};

// [4] for a drive longer than one chunk (mapper_chunks.h), each chunk mapped
// and, where folded, posed from the odometry or mapped again with other
// seeds (reconstruction_chunks.cc).
ChunkedMapping MapInChunks(ColmapRunner* colmap,
                           const ReconstructionOptions& run,
                           const MatchingRound& round,
                           const std::vector<TimedImage>& images,
                           const Trajectory& odometry,
                           const std::vector<MapperChunk>& chunks,
                           Progress* progress);

}  // namespace odomcal::reconstruction
