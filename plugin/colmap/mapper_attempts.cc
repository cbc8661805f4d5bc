#include "odomcal/plugin/colmap/mapper_attempts.h"

#include <algorithm>
#include <tuple>

namespace odomcal {
namespace {

// Lower is better: how much of an answer the calibration gave.
int StatusRank(CalibrationStatus status) {
  switch (status) {
    case CalibrationStatus::kSuccess:
      return 0;
    case CalibrationStatus::kUnobservable:
      return 1;
    case CalibrationStatus::kRefinementFailed:
      return 2;
    case CalibrationStatus::kInconsistentData:
      return 3;
    case CalibrationStatus::kNotEnoughMotion:
      return 4;
    case CalibrationStatus::kNotRun:
      return 5;
  }
  return 5;
}

}  // namespace

MapperAttempt SummarizeMapperAttempt(int random_seed,
                                     const std::string& model_path,
                                     const std::vector<ColmapSegment>& segments,
                                     const StretchCheckResult& check) {
  MapperAttempt attempt;
  attempt.random_seed = random_seed;
  attempt.model_path = model_path;
  attempt.produced_model = !segments.empty();
  attempt.num_sub_models = static_cast<int>(segments.size());
  for (const ColmapSegment& segment : segments) {
    attempt.num_registered_images += segment.num_registered_images;
  }
  attempt.status = check.result.status;
  int num_left_out = 0;
  for (const InconsistentStretch& stretch : check.stretches) {
    if (stretch.kept_as_segment) continue;
    num_left_out += stretch.num_pairs;
    attempt.contradicted_spans.emplace_back(stretch.first_stamp_ns,
                                            stretch.last_stamp_ns);
  }
  // A refusal for too little motion (straight driving, too few pairs)
  // judged no pair, so the odometry contradicts none (a straight drive stays
  // straight in every model). Any other refusal without an estimate (RANSAC
  // found no consistent set) explains no pair.
  attempt.pairs_tested =
      check.result.has_estimate ||
      (check.result.status != CalibrationStatus::kUnobservable &&
       check.result.status != CalibrationStatus::kNotEnoughMotion);
  for (const MotionPair& pair : check.pairs) {
    attempt.pair_spans.emplace_back(pair.stamp_i_ns, pair.stamp_j_ns);
  }
  const std::vector<char>& used = check.result.diagnostics.inlier_mask;
  int num_unused = 0, num_contradicting = 0;
  for (size_t k = 0; k < check.pairs.size() && attempt.pairs_tested; ++k) {
    if (check.result.has_estimate && k < used.size() && used[k] != 0) continue;
    ++num_unused;
    // Another mapper run is worth it for what the odometry contradicts,
    // not for a pair beyond only the noise estimated from the data.
    if (check.result.has_estimate && k < check.contradicts_odometry.size() &&
        check.contradicts_odometry[k] == 0) {
      continue;
    }
    ++num_contradicting;
    attempt.contradicted_spans.emplace_back(check.pairs[k].stamp_i_ns,
                                            check.pairs[k].stamp_j_ns);
  }
  std::sort(attempt.contradicted_spans.begin(),
            attempt.contradicted_spans.end());
  const int num_calibrated = static_cast<int>(check.pairs.size());
  attempt.num_pairs = num_calibrated + num_left_out;
  attempt.num_pairs_used =
      attempt.pairs_tested ? num_calibrated - num_unused : 0;
  attempt.num_contradicting_pairs = num_contradicting + num_left_out;
  attempt.num_pairs_left_out = num_left_out;
  return attempt;
}

bool OdometryAcceptsModel(const MapperAttempt& attempt) {
  return attempt.produced_model && StatusRank(attempt.status) <= 1 &&
         attempt.num_contradicting_pairs == 0;
}

bool RepeatsContradictions(const MapperAttempt& later,
                           const MapperAttempt& earlier) {
  return later.produced_model && earlier.produced_model &&
         !later.contradicted_spans.empty() &&
         later.contradicted_spans == earlier.contradicted_spans;
}

bool RepeatsUntestedPairs(const MapperAttempt& later,
                          const MapperAttempt& earlier) {
  return later.produced_model && earlier.produced_model &&
         !later.pairs_tested && !earlier.pairs_tested &&
         later.pair_spans == earlier.pair_spans;
}

bool ShouldMatchAgain(const std::vector<MapperAttempt>& round) {
  bool any_model = false;
  for (const MapperAttempt& attempt : round) {
    if (OdometryAcceptsModel(attempt)) return false;
    any_model |= attempt.produced_model;
  }
  return any_model;
}

bool IsBetterMapperAttempt(const MapperAttempt& a, const MapperAttempt& b) {
  // Tuples compare lexicographically; negated counts: more is better.
  const auto key = [](const MapperAttempt& attempt) {
    return std::make_tuple(!attempt.produced_model,
                           StatusRank(attempt.status),
                           attempt.num_contradicting_pairs,
                           -attempt.num_pairs_used,
                           -attempt.num_registered_images);
  };
  return key(a) < key(b);
}

int BestMapperAttempt(const std::vector<MapperAttempt>& attempts) {
  int best = -1;
  for (size_t i = 0; i < attempts.size(); ++i) {
    if (!attempts[i].produced_model) continue;
    if (best < 0 || IsBetterMapperAttempt(attempts[i], attempts[best])) {
      best = static_cast<int>(i);
    }
  }
  return best;
}

}  // namespace odomcal
