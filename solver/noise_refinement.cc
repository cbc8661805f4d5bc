#include "odomcal/solver/noise_refinement.h"

#include "odomcal/solver/chi_square.h"
#include "odomcal/solver/hand_eye_residual.h"
#include "odomcal/solver/parallel_chunks.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace odomcal {
namespace {

constexpr int kMaxRounds = 6;
constexpr double kFactorTolerance = 0.01;

double LargestChange(const ComponentFactors& a, const ComponentFactors& b) {
  double change = 0.0;
  for (int g = 0; g < kNumNoiseComponents; ++g) {
    change = std::max(change, std::abs(b[g] / a[g] - 1.0));
  }
  return change;
}

CalibrationOptions UnderFactors(const CalibrationOptions& options,
                                const ComponentFactors& factors) {
  CalibrationOptions weighted = options;
  weighted.noise = ScaleNoiseComponents(options.noise, factors);
  return weighted;
}

// One refinement of the rounds: its start, noise factors and pairs, and its
// result without the information (only the kept round's is computed, by
// AddInformation).
struct RefinementAtFactors {
  Rigid3d start;
  std::vector<double> start_scales;
  ComponentFactors factors;
  std::vector<int> used;
  RefinementResult result;
};

// The refinement under the noise scaled by `factors`. The scaled copy of the
// pairs lives only for it: at 10 000 pairs it is 12 MB, which would
// otherwise add to the noise estimation's peak.
RefinementAtFactors RefineUnderFactors(const MotionPairs& pairs,
                                       const std::vector<int>& used,
                                       const Rigid3d& start,
                                       const std::vector<double>& start_scales,
                                       const CalibrationOptions& options,
                                       const ComponentFactors& factors) {
  RefinementAtFactors refinement{start, start_scales, factors, used, {}};
  refinement.result =
      RefineOdomFromCam(ScaleCovariances(pairs, CovarianceFactors(factors)),
                        used,
                        start,
                        start_scales,
                        UnderFactors(options, factors),
                        TranslationZ::kHold,
                        InformationAtSolution::kSkip);
  return refinement;
}

// The information of a refinement of the rounds, as RefineOdomFromCam would
// have computed it.
void AddInformation(const MotionPairs& pairs,
                    const CalibrationOptions& options,
                    RefinementAtFactors* refinement) {
  RefinementResult& result = refinement->result;
  result.information = RefinementInformation(
      ScaleCovariances(pairs, CovarianceFactors(refinement->factors)),
      refinement->used,
      refinement->start,
      refinement->start_scales,
      UnderFactors(options, refinement->factors),
      TranslationZ::kHold,
      result,
      &result.information_segments);
}

}  // namespace

double WhitenedChiSquare(const MotionPair& pair,
                         const Rigid3d& odom_from_cam,
                         double metric_scale,
                         const NoiseModel& noise) {
  return (HandEyeSqrtInformation(pair, odom_from_cam, metric_scale, noise) *
          HandEyeResidual(pair, odom_from_cam, metric_scale))
      .squaredNorm();
}

bool IsWithinNoise(const MotionPair& pair,
                   const Rigid3d& odom_from_cam,
                   double metric_scale,
                   const NoiseModel& noise) {
  static const double kThreshold = ChiSquare999(6);
  return WhitenedChiSquare(pair, odom_from_cam, metric_scale, noise) <
         kThreshold;
}

std::vector<int> PairsWithinNoise(const MotionPairs& pairs,
                                  const Rigid3d& odom_from_cam,
                                  const std::vector<double>& metric_scales,
                                  const NoiseModel& noise,
                                  int num_threads) {
  const int num_pairs = static_cast<int>(pairs.size());
  std::vector<std::vector<int>> chunk_within(internal::NumChunks(num_pairs));
  internal::ForEachChunk(
      num_pairs, num_threads, [&](int chunk, int begin, int end) {
        for (int i = begin; i < end; ++i) {
          const size_t segment = static_cast<size_t>(pairs[i].segment);
          if (segment < metric_scales.size() && metric_scales[segment] > 0.0 &&
              IsWithinNoise(
                  pairs[i], odom_from_cam, metric_scales[segment], noise)) {
            chunk_within[chunk].push_back(i);
          }
        }
      });
  std::vector<int> within;
  for (const std::vector<int>& indices : chunk_within) {
    within.insert(within.end(), indices.begin(), indices.end());
  }
  return within;
}

NoiseRefinement RefineWithNoiseEstimation(
    const MotionPairs& pairs,
    const std::vector<int>& used,
    const Rigid3d& initial,
    const std::vector<double>& initial_scales,
    const CalibrationOptions& options) {
  NoiseRefinement result;
  result.used = used;
  result.noise.noise = options.noise;
  Rigid3d estimate = initial;
  std::vector<double> scales = initial_scales;
  ComponentFactors factors = kUnitComponentFactors;
  std::vector<int> refined_used = used;
  NoiseEstimate refined_noise = result.noise;
  // Once an estimation moves no factor by kFactorTolerance, the levels are
  // kept: the rounds after it only follow the inlier set, whose last pairs
  // at the threshold cannot move them (at 10 000 pairs an estimation costs
  // as much as a refinement).
  bool settled = false;
  RefinementAtFactors kept;
  for (int round = 0;; ++round) {
    RefinementAtFactors refinement = RefineUnderFactors(
        pairs, result.used, estimate, scales, options, factors);
    const RefinementResult& refined = refinement.result;
    if (!refined.usable) {
      // Keep the last usable refinement (the caller reports a failure when
      // the first one fails).
      if (round == 0) kept = std::move(refinement);
      result.used = refined_used;
      result.noise = refined_noise;
      break;
    }
    kept = std::move(refinement);
    refined_used = result.used;
    refined_noise = result.noise;
    result.num_rounds = round + 1;
    estimate = kept.result.odom_from_cam;
    scales = kept.result.metric_scales;
    if (round == kMaxRounds) break;

    if (!settled) {
      result.noise = EstimateNoise(pairs,
                                   result.used,
                                   estimate,
                                   scales,
                                   options,
                                   /*estimate_z=*/false,
                                   kUnitComponentFactors,
                                   /*initial_guess=*/factors);
    }
    const ComponentFactors next = result.noise.component_factors;
    std::vector<int> inliers = result.used;
    if (options.use_ransac) {
      inliers =
          PairsWithinNoise(ScaleCovariances(pairs, CovarianceFactors(next)),
                           estimate,
                           scales,
                           result.noise.noise,
                           options.num_threads);
      if (static_cast<int>(inliers.size()) < options.min_num_pairs) {
        inliers = result.used;
      }
    }
    settled = LargestChange(factors, next) < kFactorTolerance;
    const bool converged = inliers == result.used && settled;
    factors = next;
    result.used = inliers;
    if (converged) break;
  }
  if (kept.result.usable) AddInformation(pairs, options, &kept);
  result.refinement = std::move(kept.result);
  return result;
}

}  // namespace odomcal
