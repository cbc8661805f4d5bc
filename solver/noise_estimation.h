// Noise levels from the data: variance-component estimation (Foerstner's
// iteration of Helmert's estimator) over the residual groups of the hand-eye
// problem.
//
// The residual covariance of a pair (hand_eye_residual.h) is a sum over four
// groups, each the propagated covariance of one noise source:
//   Cov(r_i) = sum_g theta_g V_ig,   g = odometry rotation, odometry
//   translation, camera rotation, camera translation,
// where V_ig is the group's contribution under the given noise (the options'
// NoiseModel or the pair's own covariance) and theta_g its variance factor
// (1: the given noise is right; the standard deviations scale by
// sqrt(theta_g)). At a fixed estimate with residuals e_i, Jacobians J_i,
// P_i = Cov(r_i)^-1 and N = sum J_i^T P_i J_i, the iteration
//   theta_g <- theta_g * (sum_i e_i^T P_i V_ig P_i e_i) / (sum_i tr(V_ig M_i)),
//   M_i = P_i - P_i J_i N^-1 J_i^T P_i,
// converges to the estimate whose weighted residual sum of each group equals
// its redundancy (its share of the degrees of freedom, parameters removed).
//
// Identifiability: two groups whose contributions have (nearly) the same shape
// over the data cannot be told apart (e.g. odometry and camera translation
// noise, both proportional to the step length; camera rotation noise and
// odometry tilt noise). Their estimates are then strongly anti-correlated:
// a group whose factor has a relative standard deviation (2 H^-1, H the
// Helmert matrix sum_i tr(M_i V_ig M_i V_il)) above kMaxRelativeStddev is
// tied to the group its estimate correlates with most, and the tied groups
// share one factor. A group (or tie) that stays undetermined on its own, or
// has almost no redundancy (few pairs), keeps the given noise (factor 1).
// A factor never goes below 0.01 of the given noise's (0.1 in standard
// deviation): exact or over-fitted data would otherwise claim zero noise.
#pragma once

#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/rigid3.h"

#include <array>
#include <string>
#include <vector>

namespace odomcal {

enum class NoiseGroup {
  kOdometryRotation = 0,     // odom_yaw_sigma_*, odom_tilt_sigma_deg
  kOdometryTranslation = 1,  // odom_translation_sigma_*
  kCameraRotation = 2,       // cam_rotation_sigma_deg
  kCameraTranslation = 3,    // cam_translation_sigma_rel
};
constexpr int kNumNoiseGroups = 4;

// "odometry rotation", ... (used in messages and the JSON).
std::string ToString(NoiseGroup group);

// Variance factor per group, indexed by NoiseGroup.
using NoiseFactors = std::array<double, kNumNoiseGroups>;
constexpr NoiseFactors kUnitNoiseFactors = {1.0, 1.0, 1.0, 1.0};

// The noise model with each group's standard deviations scaled by
// sqrt(factor).
NoiseModel ScaleNoise(const NoiseModel& noise, const NoiseFactors& factors);

// The pairs with their own covariances (where present) scaled by group: the
// rotation and translation blocks by their factors, the cross blocks by the
// geometric mean.
MotionPairs ScaleCovariances(const MotionPairs& pairs,
                             const NoiseFactors& factors);

struct NoiseEstimate {
  NoiseFactors variance_factors = kUnitNoiseFactors;
  // Per group: estimated (alone or tied) or kept at the given noise.
  std::array<bool, kNumNoiseGroups> estimated = {false, false, false, false};
  // Groups with the same tie index share one factor; tie[g] is the smallest
  // group index of g's tie (tie[g] == g for a group of its own).
  std::array<int, kNumNoiseGroups> tie = {0, 1, 2, 3};
  // Redundancy share of each group (sum over groups: observations minus
  // parameters) and the relative standard deviation of its factor.
  std::array<double, kNumNoiseGroups> redundancy = {0.0, 0.0, 0.0, 0.0};
  std::array<double, kNumNoiseGroups> factor_relative_stddev = {0, 0, 0, 0};
  int num_pairs = 0;
  int num_iterations = 0;
  NoiseModel noise;  // the given NoiseModel scaled by the factors

  bool Tied(NoiseGroup a, NoiseGroup b) const {
    return tie[static_cast<int>(a)] == tie[static_cast<int>(b)];
  }
  // Standard deviation ratio sqrt(factor) of a group.
  double SigmaRatio(NoiseGroup group) const;
};

// Relative standard deviation of a factor above which its group is not
// separable (tied) or not determined (kept).
constexpr double kMaxRelativeStddev = 0.5;

// Variance components of pairs[used] at a fixed estimate, starting from
// `start` factors relative to options.noise / the pairs' own covariances.
// Parameters: rotation (3), translation x, y (and z when estimate_z), one
// scale per segment among `used`.
NoiseEstimate EstimateNoise(const MotionPairs& pairs,
                            const std::vector<int>& used,
                            const Rigid3d& odom_from_cam,
                            const std::vector<double>& metric_scales,
                            const CalibrationOptions& options,
                            bool estimate_z = false,
                            const NoiseFactors& start = kUnitNoiseFactors);

// "noise estimated from 118 pairs (standard deviations relative to the given
// model): odometry rotation x1.8, odometry translation and camera translation
// (tied) x0.9, camera rotation x2.1 (kept: not separable)".
std::string NoiseSummary(const NoiseEstimate& estimate);

}  // namespace odomcal
