// Noise levels from the data: variance-component estimation (Foerstner's
// iteration of Helmert's estimator, as Fisher scoring of the restricted
// likelihood) over the noise components of the hand-eye problem.
//
// The residual covariance of a pair (hand_eye_residual.h) is built from the
// NoiseModel (or the pair's own covariances). Its components are the model's
// standard deviations, each scaled by sqrt(mu_k), mu_k the component's
// variance factor (1: the given noise is right):
//   odometry yaw, constant and proportional part (odom_yaw_sigma_deg,
//   odom_yaw_sigma_rel), odometry tilt, odometry translation, constant and
//   proportional part (odom_translation_sigma_m, odom_translation_sigma_rel),
//   camera rotation, camera translation across and along the direction of
//   motion (cam_translation_sigma_rel, cam_translation_along_sigma_rel), and
//   the rotation and translation blocks of the pairs' own covariances.
// The odometry tilt is kept as given, not estimated: it is the planarity
// the model assumes, which the planarity check (planarity_check.h) tests.
// The factors can therefore change the noise's shape, not only its level
// (e.g. a camera whose translation error is a direction error, odometry
// whose translation noise is proportional to the length). A constant and a
// proportional part add as standard deviations, so Cov(r_i) is a quadratic
// form in sqrt(mu): sum_kl sqrt(mu_k mu_l) W_ikl. At a fixed estimate with
// residuals e_i, Jacobians J_i, P_i = Cov(r_i)^-1, N = sum J_i^T P_i J_i,
// M_i = P_i - P_i J_i N^-1 J_i^T P_i and D_ik = d Cov(r_i) / d mu_k, the
// step mu <- mu + H^-1 (q - t) with q_k = sum e_i^T P_i D_ik P_i e_i,
// t_k = sum tr(D_ik M_i), H_kl = sum tr(M_i D_ik M_i D_il) (Helmert's
// estimator where Cov is linear in mu) converges to the estimate whose
// weighted residual sum of each component equals its redundancy.
//
// Identifiability: components whose contributions have (nearly) the same
// shape over the data cannot be told apart (e.g. odometry and camera
// translation noise, both proportional to the step length; the constant and
// proportional part of a short drive's steps). Their estimates are then
// strongly anti-correlated: a component whose factor has a standard deviation
// (2 H^-1) above kMaxRelativeStddev times its group's largest factor is
// tied to the component its estimate correlates with most, and tied
// components share one factor. A component (or tie) that stays undetermined
// on its own, or has almost no redundancy (few pairs), keeps the given noise
// (factor 1).
//
// Optionally the given noise is a prior as well as a start
// (options.noise_prior_weight > 0): each estimated level carries that many
// pseudo-observations of the given noise (a scaled inverse chi-square prior;
// for one linear component the estimate is (S + w) / (r + w), S the weighted
// residual sum and r the redundancy). Off by default: with 20 pairs whose
// given noise has the wrong shape it costs 5-9 % of accuracy
// (docs/statistics.md).
// A standard deviation is estimated within [0.1x, 10x] the given one
// (kNoiseSigmaRatioFloor, kNoiseSigmaRatioCeiling); both bounds are
// reported (component_bound). A level at the ceiling is a finding, not an
// estimate: one component takes up an error the noise model does not
// describe (a systematic error, a wrong unit). It keeps the given noise, the
// others are estimated again, and where the fit's chi-square then exceeds
// its redundancy the covariance is widened by the excess (misfit_widening).
// A level at the floor is held there: exact or over-fitted data (simulations,
// a handful of pairs) would otherwise claim zero noise. A factor at the
// floor whose data ask for less is held out of the Fisher step and the tie
// decisions (an active set).
#pragma once

#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/noise_components.h"
#include "odomcal/solver/noise_scaling.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>

#include <array>
#include <string>
#include <vector>

namespace odomcal {

// The range of an estimated standard deviation, relative to the given one.
inline constexpr double kNoiseSigmaRatioFloor = 0.1;
inline constexpr double kNoiseSigmaRatioCeiling = 10.0;

// Where a component's estimate ended: inside the range, or at a bound.
enum class NoiseBound { kNone, kFloor, kCeiling };
std::string ToString(NoiseBound bound);

struct NoiseEstimate {
  // Per group: the ratio of the estimated to the given contribution to the
  // residual covariance (traces summed over the pairs): the level of the
  // group's noise, whatever its shape.
  NoiseFactors variance_factors = kUnitNoiseFactors;
  // Per group: some component estimated (alone or tied) or all kept.
  std::array<bool, kNumNoiseGroups> estimated = {false, false, false, false};
  // Groups with a component in the same tie; tie[g] is the smallest group
  // index of g's ties (tie[g] == g for a group of its own).
  std::array<int, kNumNoiseGroups> tie = {0, 1, 2, 3};
  // Redundancy share of each group (sum over groups: observations minus
  // parameters) and the largest relative standard deviation of its
  // estimated components' factors.
  std::array<double, kNumNoiseGroups> redundancy = {0.0, 0.0, 0.0, 0.0};
  std::array<double, kNumNoiseGroups> factor_relative_stddev = {0, 0, 0, 0};

  // Per component (NoiseComponent): the factor relative to the given noise,
  // whether the data contain it (non-zero given noise or own covariances),
  // estimated (alone or tied), its tie (the smallest component index of
  // the components sharing its factor) and its factor's relative standard
  // deviation.
  ComponentFactors component_factors = kUnitComponentFactors;
  std::array<bool, kNumNoiseComponents> component_present = {};
  std::array<bool, kNumNoiseComponents> component_estimated = {};
  std::array<int, kNumNoiseComponents> component_tie = {
      0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
  std::array<double, kNumNoiseComponents> component_relative_stddev = {};
  // Components whose level ran to a bound: at the floor, held there; at the
  // ceiling, kept at the given noise and not estimated (see above).
  std::array<NoiseBound, kNumNoiseComponents> component_bound = {};
  // sqrt(chi-square / redundancy) of the pairs under the final noise when a
  // component was kept at the ceiling and the fit exceeds its redundancy,
  // else 1. The calibration divides the information by its square.
  double misfit_widening = 1.0;

  // The estimate's covariance with this noise is Phi + 2 Phi A Phi (Kenward
  // and Roger 1997), Phi the inverse information under the noise and A this
  // term: the estimated factors' own uncertainty (few pairs) widens it.
  // Columns: rotation (3), translation x, y, then one scale per segment of
  // kenward_roger_segments (ascending). Empty when nothing was estimated or
  // z was (estimate_z).
  Eigen::MatrixXd kenward_roger_term;
  std::vector<int> kenward_roger_segments;
  // Set by the calibration (WidenForEstimatedNoise): the largest ratio, over
  // the estimate's parameters, of the standard deviation with that widening
  // to the one without (1: not widened).
  double stddev_widening = 1.0;

  int num_pairs = 0;
  int num_iterations = 0;
  // The given NoiseModel scaled by the component factors: the noise the
  // covariance uses (with ScaleCovariances(pairs, CovarianceFactors(
  // component_factors)) for pairs with their own covariances).
  NoiseModel noise;

  bool Tied(NoiseGroup a, NoiseGroup b) const {
    return tie[static_cast<int>(a)] == tie[static_cast<int>(b)];
  }
  // Standard deviation ratio sqrt(factor) of a group (its level).
  double SigmaRatio(NoiseGroup group) const;
  // Standard deviation ratio sqrt(factor) of a component.
  double SigmaRatio(NoiseComponent component) const;
};

// The pairs weighted as the covariance under `estimate` weighs them: their
// own covariances scaled by CovarianceFactors(estimate.component_factors).
// Pair them with estimate.noise.
MotionPairs ScaleCovariances(const MotionPairs& pairs,
                             const NoiseEstimate& estimate);

// Relative standard deviation of a factor above which its component is not
// separable (tied) or not determined (kept).
constexpr double kMaxRelativeStddev = 0.5;

// Variance components of pairs[used] at a fixed estimate, relative to
// `start` factors of options.noise / the pairs' own covariances (the bounds
// on the estimate are multiples of `start`). The scoring starts from
// `initial_guess` (factors, e.g. the last round's estimate): the iteration
// converges to the same estimate from any start, in fewer steps from a
// close one. Parameters: rotation (3), translation x, y (and z when
// estimate_z), one scale per segment among `used`.
NoiseEstimate EstimateNoise(
    const MotionPairs& pairs,
    const std::vector<int>& used,
    const Rigid3d& odom_from_cam,
    const std::vector<double>& metric_scales,
    const CalibrationOptions& options,
    bool estimate_z = false,
    const ComponentFactors& start = kUnitComponentFactors,
    const ComponentFactors& initial_guess = kUnitComponentFactors);

// The information N of the refinement (columns: rotation, translation x, y,
// one scale per entry of `information_segments`, then z if estimated)
// widened for the noise's estimation: (Phi + 2 Phi A Phi)^-1 = N (N + 2 A)^-1
// N, with A = estimate.kenward_roger_term mapped onto these columns (none
// for z: the noise was estimated with z held). Returns `information` when
// the estimate has no term. `stddev_widening` (optional): the largest ratio
// of a parameter's standard deviation after to before.
Eigen::MatrixXd WidenForEstimatedNoise(
    const Eigen::MatrixXd& information,
    const std::vector<int>& information_segments,
    const NoiseEstimate& estimate,
    double* stddev_widening = nullptr);

// "noise estimated from 118 pairs (standard deviations relative to the given
// noise): odometry yaw, constant part x1.8, odometry translation,
// proportional part and camera translation, along the motion (tied: not
// separable) x0.9, ...; kept as given: camera rotation (not determined by
// these pairs)". Components the data do not contain (zero
// given noise, no own covariances) and the odometry tilt are not listed.
std::string NoiseSummary(const NoiseEstimate& estimate);

}  // namespace odomcal
