// SfM scale drift inside a segment, as a term of the covariance.
//
// The calibration fits one metric scale per segment (and the step-length
// check of scale_consistency.h cuts a segment where its scale changes by a
// step or a trend it can detect). What remains is a slow wander of the
// reconstruction's scale along the path, below the check's threshold: on a
// forward drive, the scale of a left turn and that of a right turn a minute
// later differ by a few tenths of a percent. The lever arm takes up such a
// difference: a turn of radius R at a relative scale error e moves the lever
// arm across the turn by about R e / 2, so a 15 m turn 0.2 % off moves y by
// 15 mm, beyond a covariance that treats each segment's scale as one number.
//
// The wander is modelled as a random walk of the relative scale in time,
// e(t) = e(t0) + W(t) with Var W(t) = q (t - t0), inside every segment (the
// segment's own scale takes up e(t0)). Its rate q is estimated from the
// per-pair scales (PerPairMetricScales): a local-level model, the random walk
// plus each pair's own scatter (its first-order variance times a common
// factor c), whose likelihood a Kalman filter evaluates exactly with the
// segment's level free (diffuse start); c is concentrated out and q = c r
// with r maximising the profile likelihood over a grid, refined by golden
// section. A model whose scale does not wander gives r = 0 and no term.
//
// The term is the estimate's first-order response to the wander:
//   Cov = H^-1 B K B^T H^-1,
// H the information of the fit, B's column i the change of its gradient per
// relative scale change of pair i alone (hand_eye_refine.h), and K the
// random walk's covariance over the pairs' mid times, K_ij = q min(t_i, t_j)
// from the segment's first pair, taken about its mean over the segment (B's
// columns centred per segment): a constant wander only changes the
// segment's scale, so the extrinsic's term is zero for it, and the scale's
// holds what the wander does to the segment's scale as a whole, not the
// walk's distance from its start.
#pragma once

#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/rigid3.h"
#include "odomcal/solver/scale_consistency.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace odomcal {

// The random walk's rate, estimated from the per-pair scales.
struct ScaleDriftRate {
  // False with fewer than kMinPairs pairs of finite scale over all segments
  // that hold at least 3: q is then 0.
  bool estimated = false;
  int num_pairs = 0;     // pairs that entered the likelihood
  int num_segments = 0;  // segments with at least 3 of them
  // Variance of the relative scale per second of the random walk (1/s).
  double rate_per_s = 0.0;
  // The pairs' scatter over their first-order variance (c above).
  double scatter_factor = 0.0;
  // Twice the log-likelihood gained over q = 0 (0 when q = 0); about
  // chi-square with one degree of freedom, at the boundary, without drift.
  double likelihood_ratio = 0.0;

  static constexpr int kMinPairs = 10;
  // The walk joins the covariance only where it is significant at 5 %: the
  // 95 % point of the likelihood ratio without drift, half chi-square(0)
  // and half chi-square(1) (q = 0 lies on the boundary), is chi-square(1)'s
  // 90 % point. Independent per-pair scale errors whose variance the noise
  // model has wrong in shape can otherwise favour a small walk by chance.
  static constexpr double kSignificantLikelihoodRatio = 2.706;
};

// `pair_scales` is PerPairMetricScales() of `pairs` under the fit;
// `metric_scales` the fit's scales per segment; only `used` pairs count, in
// time order within each segment. Never throws.
ScaleDriftRate EstimateScaleDriftRate(
    const MotionPairs& pairs,
    const std::vector<int>& used,
    const std::vector<PairMetricScale>& pair_scales,
    const std::vector<double>& metric_scales);

// H^-1 B C K C^T B^T H^-1 (C centres per segment) for `information` (H)
// and `sensitivity` (B, one column
// per entry of `used`, as HandEyeScaleSensitivity returns them) under the
// random walk `rate_per_s`. Empty when H cannot be inverted or the inputs
// do not match.
Eigen::MatrixXd ScaleDriftCovariance(const MotionPairs& pairs,
                                     const std::vector<int>& used,
                                     const Eigen::MatrixXd& information,
                                     const Eigen::MatrixXd& sensitivity,
                                     double rate_per_s);

// The calibration's use of it: the rate, and the standard deviations of
// rx, ry, rz (deg, small-angle axes) and x, y (m) without and with the term.
struct ScaleDriftTerm {
  ScaleDriftRate rate;
  // The term joined the covariance: q > 0 and likelihood_ratio above
  // ScaleDriftRate::kSignificantLikelihoodRatio.
  bool applied = false;
  Eigen::Matrix<double, 5, 1> stddev_before =
      Eigen::Matrix<double, 5, 1>::Zero();
  Eigen::Matrix<double, 5, 1> stddev_after =
      Eigen::Matrix<double, 5, 1>::Zero();
  // Applied and widening one of them beyond its standard deviation without it
  // (the term alone larger): the result carries ScaleDriftWarning().
  bool named = false;
};

// Estimates the rate from `pairs` (weighted as the fit weighs them) under
// the fit (`odom_from_cam`, `metric_scales`, `options.noise`), and adds the
// term to the covariance that `information` ([rx, ry, rz, tx, ty, one scale
// per `information_segments`, tz when its row is there]) inverts to:
// `information` is replaced by the inverse of the widened covariance.
// `z_prior_information` is the prior's information on tz (0 without one),
// which the fit had and `information` holds. Leaves `information` as it is
// where the rate is 0 or a matrix cannot be inverted.
ScaleDriftTerm AddScaleDriftCovariance(
    const MotionPairs& pairs,
    const std::vector<int>& used,
    const Rigid3d& odom_from_cam,
    const std::vector<double>& metric_scales,
    const CalibrationOptions& options,
    const std::vector<int>& information_segments,
    double z_prior_information,
    Eigen::MatrixXd* information);

// "the reconstruction's scale wanders along the drive: ..." for a named term.
std::string ScaleDriftWarning(const ScaleDriftTerm& term);

}  // namespace odomcal
