// Step-length consistency: SfM scale drift seen through the odometry.
//
// Under one extrinsic X = (R, p) every motion pair implies a metric scale of
// its own, from the translation part of  A X = X B(s):
//   s R t_B = R_A p + t_A - p.
// Within a segment these per-pair scales should scatter around one value.
// An incremental reconstruction that drifts in scale (or joins two parts at
// different scales without a visible fold) shows them changing along the
// path, which every pair still "explains" within the per-pair thresholds of
// RANSAC. This step finds such changes by binary segmentation: the split of a
// segment into two constant-scale parts that most reduces the weighted
// chi-square is accepted when an F-test against the two-part fit's own
// scatter is significant and the scale change is large enough to matter, or
// when a linear trend of the scale over time is (a gradual drift, whose
// within-part trend would otherwise inflate the step test's scatter).
//
// The lever arm's x/y is fitted jointly (one for all parts of a segment):
// a lever arm error biases only the scales of turning pairs (through
// (R_A - I) p), so a wrong or undetermined lever arm (unobservable x/y) must
// not read as a change of scale, nor a change of scale hide in it. Straight
// pairs give the scale from the rotation and the step lengths alone. The
// threshold of the F-test follows from a false-cut probability, Bonferroni-
// corrected for the split points searched, and the degrees of freedom.
#pragma once

#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace odomcal {

// The scale one pair implies and its first-order standard deviation under
// the noise model (infinite for pairs without camera translation).
struct PairMetricScale {
  double scale = 0.0;
  double stddev = 0.0;
  // d scale / d (lever arm x, y): zero for pairs that do not turn.
  Eigen::Vector2d scale_per_lever_arm_xy = Eigen::Vector2d::Zero();
};

// Generalised least squares of  r_t(s) = d - s u  for each pair alone, with
// the residual covariance evaluated at its segment's scale.
std::vector<PairMetricScale> PerPairMetricScales(
    const MotionPairs& pairs,
    const Rigid3d& odom_from_cam,
    const std::vector<double>& metric_scales,
    const NoiseModel& noise);

struct ScaleChangeOptions {
  int min_pairs_per_part = 6;         // each side determines its own scale
  double min_relative_change = 0.01;  // smaller changes are not worth a cut
  // Probability that a segment whose scale does not change is cut (per
  // test of a segment): half for the step test, whose F threshold is the
  // F(1, n - 4) critical value at that half over the number of split points
  // (Bonferroni), half for the trend test (F(1, n - 4) at that half).
  double false_cut_probability = 1e-3;
  // Enough parts for a drift of 10 % to leave under 1.5 % within a part.
  int max_changes_per_segment = 7;
};

struct ScaleChange {
  int segment = 0;  // of the input pairs
  int first_pair_after =
      0;                 // index into the input pairs: first of the new part
  int64_t stamp_ns = 0;  // stamp_i of that pair
  double scale_before = 0.0;  // joint fit of the parts and the lever arm
  double scale_after = 0.0;
  double f_statistic = 0.0;
  double f_threshold = 0.0;  // the critical value it exceeded
};

// Changes within each segment of `pairs` (time-ordered within a segment, as
// association produces them), in segment and time order. `pair_scales` is
// PerPairMetricScales() of the same pairs.
std::vector<ScaleChange> FindScaleChanges(
    const MotionPairs& pairs,
    const std::vector<PairMetricScale>& pair_scales,
    const ScaleChangeOptions& options);

}  // namespace odomcal
