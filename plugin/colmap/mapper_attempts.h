// Choosing among COLMAP mapper runs by what the odometry says of them.
//
// Given one database, COLMAP 3.8's incremental mapper can return, for one
// random seed, a model with a few images registered degrees off, and for
// the next seed a clean one. Measured on the `tilted` preset, seed 4: the
// default seed gave 2 of 34 motion pairs 2 deg off the odometry and put
// 0.15-0.24 deg into the extrinsic; seeds 1, 2 and 3 on the same database
// gave 34 of 34 pairs and 0.03 deg. The odometry sees such a model as
// motion pairs that no extrinsic explains, so `odomcal run` maps again with
// another seed while it does, and keeps the model it contradicts least.
//
// When the seeds do not help, the matches may be at fault. COLMAP's two-view
// verification is random too (given one database the mapper is
// deterministic; the runs differ through matching), so `odomcal run` then
// matches again and maps the new matches; see ShouldMatchAgain.
#pragma once

#include "odomcal/adapters/colmap_segments.h"
#include "odomcal/solver/calibration_result.h"
#include "odomcal/solver/stretch_consistency.h"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace odomcal {

struct MapperAttempt {
  int matching_round = 0;  // 0: the first matches; 1: matched again
  // A chunked drive (mapper_chunks.h): the chunk mapped again with
  // `random_seed`, the others as chosen before; -1: every chunk mapped
  // with seed 0, or a drive of one model.
  int chunk = -1;
  int random_seed = 0;  // COLMAP's --random_seed
  // The chunk's model (mapped with `random_seed`) with its folded stretches
  // posed again from the odometry, triangulated and adjusted again
  // (fold_reposing.h).
  bool posed_from_odometry = false;
  // How COLMAP's mapper started the model (mapper_initialization.h):
  // "colmap_search", "odometry_pair", "relaxed_search",
  // "relaxed_odometry_pair" or "neighbour_window"; the initial pair's image
  // names when odomcal passed one; why a run gave no model, from COLMAP's
  // log ("" when it gave one). A combination of chunk models has no
  // `initialization` (""): each chunk's own runs say how it started.
  std::string initialization = "colmap_search";
  std::vector<std::string> initial_pair;
  std::string failure_cause;
  // The mapper's output root (sub-models 0, 1, ...); a chunked drive's
  // combination of chunk models when it produced one.
  std::string model_path;
  bool produced_model = false;
  int num_sub_models = 0;
  int num_registered_images = 0;                          // over all sub-models
  CalibrationStatus status = CalibrationStatus::kNotRun;  // on this model
  int num_pairs = 0;       // motion pairs the model gives
  int num_pairs_used = 0;  // in the final fit
  // Pairs the odometry contradicts: rejected as outliers beyond RANSAC's
  // gate (ContradictsOdometry, stretch_consistency.h), or inside a stretch
  // left out as folded.
  int num_contradicting_pairs = 0;
  int num_pairs_left_out = 0;  // of those, in stretches left out as folded
  // Where: [first, last] stamp of each such pair or left-out stretch.
  std::vector<std::pair<int64_t, int64_t>> contradicted_spans;
  // False when the calibration refused for too little motion (straight
  // driving, too few pairs) before testing any pair against the odometry.
  bool pairs_tested = false;
  std::vector<std::pair<int64_t, int64_t>> pair_spans;  // every motion pair
};

// What the calibration on one attempt's model found.
MapperAttempt SummarizeMapperAttempt(int random_seed,
                                     const std::string& model_path,
                                     const std::vector<ColmapSegment>& segments,
                                     const StretchCheckResult& check);

// True when another attempt has nothing to improve: the calibration gave an
// answer (or found a quantity unobservable, which the motion decides, not
// the model) and no motion pair contradicts the odometry.
bool OdometryAcceptsModel(const MapperAttempt& attempt);

// True when `later` is contradicted exactly where `earlier` was: another
// seed changed nothing there, so a further seed would not help; on new
// matches (ShouldMatchAgain), neither would further matching.
bool RepeatsContradictions(const MapperAttempt& later,
                           const MapperAttempt& earlier);

// True when neither model's pairs could be tested (too little motion) and
// `later` gives the same motion pairs as `earlier`: a further seed would
// give the same refusal.
bool RepeatsUntestedPairs(const MapperAttempt& later,
                          const MapperAttempt& earlier);

// Whether to match again after the mapper runs `round` of one matching: yes
// when models came out but the odometry accepted none. Seeds that repeat
// the same contradictions show that the mapper's randomness is not the
// cause; new matches tell the matches' fault (the contradictions move or
// vanish) from the odometry's or the scene's (they stay).
bool ShouldMatchAgain(const std::vector<MapperAttempt>& round);

// "a is a better model than b": a model at all; then a status closer to
// success; then fewer contradicting pairs (their errors leak into the
// estimate: a smaller clean model is less precise but says so); then more
// pairs used; then more registered images.
bool IsBetterMapperAttempt(const MapperAttempt& a, const MapperAttempt& b);

// Index of the best attempt (the earliest of equals), or -1 when no attempt
// produced a model.
int BestMapperAttempt(const std::vector<MapperAttempt>& attempts);

}  // namespace odomcal
