// Odometry as the independent witness of an SfM reconstruction.
//
// SfM can return a model that looks fine (every image registered, sub-pixel
// reprojection error) yet has a folded stretch or parts at different scales.
// Such a stretch shows up as a run of consecutive motion pairs that no
// extrinsic explains. This step calibrates once, finds runs of consecutive
// pairs the fit did not use that hold at least `min_run_pairs` pairs which
// contradict the odometry (ContradictsOdometry) inside a segment, and cuts
// the segment there: the run is tested on its own (with its own scale) and
// kept as a separate segment when it is self-consistent (a part at another
// scale), otherwise dropped (a folded part); the pairs after a run continue as
// a new segment, since the scale may have changed across it. The calibration is
// then repeated on the relabelled pairs. Last, the step-length check of
// scale_consistency.h cuts segments whose scale changes along the path (SfM
// scale drift) into parts with scales of their own, and calibrates again.
// It runs whenever the calibration has an estimate, whatever its status: the
// rotation and the step lengths give the scale of a stretch even when the
// lever arm is undetermined (it is fitted as a nuisance), and a drift must
// be named most of all when the answer is otherwise doubtful.
#pragma once

#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/calibration_result.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/scale_consistency.h"

#include <cstdint>
#include <vector>

namespace odomcal {

struct StretchOptions {
  // Unused runs with fewer pairs that contradict the odometry are ordinary
  // outliers.
  int min_run_pairs = 3;
  double min_inlier_ratio =
      0.7;  // a run kept as its own segment fits this well
  bool check_scale_changes = true;
  ScaleChangeOptions scale_change;
};

// A segment cut where its metric scale changes (scale_consistency.h).
struct ScaleChangeCut {
  int input_segment = 0;
  int64_t stamp_ns = 0;       // the first pair after the cut starts here
  double scale_before = 0.0;  // metres per reconstruction unit
  double scale_after = 0.0;
  double f_statistic = 0.0;
  double f_threshold = 0.0;  // its critical value (scale_consistency.h)
};

// A stretch of an input segment calibrated with a scale of its own.
struct ScaleStretch {
  int output_segment = 0;
  int64_t first_stamp_ns = 0;  // span of its motion pairs
  int64_t last_stamp_ns = 0;
};

// An input segment the step-length check cut: how much its scale drifts,
// from a weighted linear trend of the per-pair scales over time (lever arm
// x/y fitted jointly), and the stretches it was calibrated as.
struct ScaleDrift {
  int input_segment = 0;
  int64_t first_stamp_ns = 0;
  int64_t last_stamp_ns = 0;
  // Scale at the last stamp over the scale at the first, minus 1.
  double relative_drift = 0.0;
  double relative_drift_stddev = 0.0;   // scatter-scaled, first order
  std::vector<ScaleStretch> stretches;  // in time order
  // False when too few pairs (< 5) fit the trend: relative_drift and its
  // stddev are then not measured (0).
  bool trend_measured = false;
};

struct InconsistentStretch {
  int input_segment = 0;
  int first_pair = 0;  // indices into the input pairs, inclusive
  int last_pair = 0;
  int64_t first_stamp_ns = 0;  // stamp_i of the first pair
  int64_t last_stamp_ns = 0;   // stamp_j of the last pair
  int num_pairs = 0;
  bool kept_as_segment = false;
  int output_segment = -1;  // when kept
};

// A pair contradicts the odometry when the fit did not use it and it lies
// outside RANSAC's gate under the fit (its fixed thresholds, or the given
// noise; hand_eye_ransac.h). A pair beyond only the noise estimated from
// the data is an ordinary outlier of a noise model with heavier tails, not
// a sign of a folded model: measured on the 1 000-image `long` drive,
// COLMAP's relative rotations at turns were 0.1-0.2 deg off (translations
// within 1 mm, the scale within 2 %) where the other pairs agreed to
// 0.015 deg; taken as folds, these runs became 7 segments of undetermined
// scale and 35 images were dropped from the metric output.
bool ContradictsOdometry(const MotionPair& pair,
                         bool used,
                         const CalibrationResult& fit,
                         const CalibrationOptions& options);

struct StretchCheckResult {
  CalibrationResult result;  // final calibration
  MotionPairs pairs;         // the pairs it used, relabelled segments
  // Per pair of `pairs`: ContradictsOdometry under the final fit (without
  // an estimate, every pair it did not use: nothing explains them).
  std::vector<char> contradicts_odometry;
  std::vector<int> input_pair_of_output;  // index of each output pair
  std::vector<int> input_segment_of_output_segment;
  std::vector<InconsistentStretch> stretches;
  std::vector<ScaleChangeCut> scale_changes;
  std::vector<ScaleDrift> scale_drifts;  // one per input segment with cuts
  bool split = false;                    // whether segments were cut
};

// Pairs of one segment must be in time order (as association produces them).
StretchCheckResult CalibrateWithStretchCheck(
    const MotionPairs& pairs,
    const CalibrationOptions& options,
    const StretchOptions& stretch_options);

}  // namespace odomcal
