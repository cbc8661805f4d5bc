// The batch refinement with the noise levels estimated from the data
// (noise_estimation.h) and the final inlier test under them.
//
// Rounds of: refine under the current noise; estimate the variance factors
// on the pairs in use; with options.use_ransac, choose the pairs again as
// those whose whitened residual W r (hand_eye_residual.h) has a squared norm
// below the 99.9 % point of chi-square with 6 degrees of freedom under the
// estimated noise; until neither the pairs nor the factors (1 %) change.
// Once the factors have settled they are kept, and the rounds that follow
// only refine and test again until the pairs settle too.
// RANSAC's first choice is made under the given noise (and its fixed
// thresholds) and can reject good pairs when the given noise is too small;
// this test brings them back, and removes pairs the estimated noise cannot
// explain.
#pragma once

#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/hand_eye_refine.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/noise_estimation.h"
#include "odomcal/solver/rigid3.h"

#include <vector>

namespace odomcal {

// |W r|^2 of a pair under the given noise (the pair's own covariances, where
// present, are used as they are).
double WhitenedChiSquare(const MotionPair& pair,
                         const Rigid3d& odom_from_cam,
                         double metric_scale,
                         const NoiseModel& noise);

// The final inlier test: WhitenedChiSquare below ChiSquare999(6).
bool IsWithinNoise(const MotionPair& pair,
                   const Rigid3d& odom_from_cam,
                   double metric_scale,
                   const NoiseModel& noise);

// The indices of the pairs that pass IsWithinNoise at odom_from_cam and the
// metric scale of their segment; a pair whose segment has no positive scale
// in `metric_scales` fails.
// `num_threads`: as CalibrationOptions::num_threads (the result does not
// depend on it).
std::vector<int> PairsWithinNoise(const MotionPairs& pairs,
                                  const Rigid3d& odom_from_cam,
                                  const std::vector<double>& metric_scales,
                                  const NoiseModel& noise,
                                  int num_threads = 1);

struct NoiseRefinement {
  RefinementResult refinement;  // the last one; usable: see its field
  std::vector<int> used;        // the pairs of the last refinement
  NoiseEstimate noise;          // the factors the result's covariance uses
  int num_rounds = 0;
};

// Starts from `initial` / `initial_scales` on pairs[used] (RANSAC's choice).
NoiseRefinement RefineWithNoiseEstimation(
    const MotionPairs& pairs,
    const std::vector<int>& used,
    const Rigid3d& initial,
    const std::vector<double>& initial_scales,
    const CalibrationOptions& options);

}  // namespace odomcal
