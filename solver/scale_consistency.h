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
// scatter is significant and the scale change is large enough to matter.
#pragma once

#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/rigid3.h"

#include <cstdint>
#include <vector>

namespace odomcal {

// The scale one pair implies and its first-order standard deviation under
// the noise model (infinite for pairs without camera translation).
struct PairMetricScale {
  double scale = 0.0;
  double stddev = 0.0;
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
  // F = (chi2_one - chi2_two) / (chi2_two / (n - 2)); searching all split
  // points inflates it, hence far above the single-test 1 % point (~7).
  double min_f_statistic = 30.0;
  int max_changes_per_segment = 3;
};

struct ScaleChange {
  int segment = 0;  // of the input pairs
  int first_pair_after =
      0;                 // index into the input pairs: first of the new part
  int64_t stamp_ns = 0;  // stamp_i of that pair
  double scale_before = 0.0;  // weighted means of the per-pair scales
  double scale_after = 0.0;
  double f_statistic = 0.0;
};

// Changes within each segment of `pairs` (time-ordered within a segment, as
// association produces them), in segment and time order. `pair_scales` is
// PerPairMetricScales() of the same pairs.
std::vector<ScaleChange> FindScaleChanges(
    const MotionPairs& pairs,
    const std::vector<PairMetricScale>& pair_scales,
    const ScaleChangeOptions& options);

}  // namespace odomcal
