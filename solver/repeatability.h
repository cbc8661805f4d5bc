// Does the calibration repeat? The motion pairs the final calibration used
// are cut into time blocks (halves, and quarters where each has enough
// turning); each block is calibrated on its own with the final noise model,
// and a chi-square test asks whether the blocks' extrinsics (and metric
// scale, for a single segment) agree within their covariances. A camera
// mount that moved during the drive (a knock, a loose bracket) makes the
// blocks before and after it disagree: when a test fails, every split time
// of a grid is tried and the one whose two sides disagree most is named.
//
// The statistic of K blocks with estimates x_k and covariances C_k is
//   T = sum_k (x_k - x_bar)^T C_k^-1 (x_k - x_bar),
// x_bar the information-weighted mean; T ~ chi-square((K - 1) p) when the
// blocks measure one extrinsic (the blocks share no pair, so their errors
// are independent). x is the rotation as a rotation vector relative to the
// whole drive's (left perturbation, radians), translation x and y (metres)
// and, with one segment, its metric scale: p = 5 or 6. The halves' and the
// quarters' tests each get half of alarm_probability (Bonferroni), so that
// a drive that repeats raises an alarm with at most that probability.
#pragma once

#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/calibration_result.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace odomcal {

struct RepeatabilityOptions {
  // Probability that a drive whose extrinsic did not change raises the
  // alarm (over the halves' and the quarters' tests together).
  double alarm_probability = 0.01;
  // A block is calibrated when it holds at least this many pairs, of which
  // this many turn by at least CalibrationOptions::min_rotation_deg.
  int min_pairs_per_block = 12;
  int min_turning_pairs_per_block = 6;
  // Split times tried to name the time of a change: this many, evenly
  // between 10 % and 90 % of the drive.
  int num_split_times = 17;

  // Throws std::invalid_argument naming the field.
  void Check() const;
};

struct RepeatabilityBlock {
  int64_t first_stamp_ns = 0;  // the first pair's start
  int64_t last_stamp_ns = 0;   // the last pair's end
  int num_pairs = 0;
  bool calibrated = false;
  std::string reason;  // why not, when not calibrated
  Rigid3d odom_from_cam;
  Eigen::Vector3d roll_pitch_yaw_deg = Eigen::Vector3d::Zero();
  Eigen::Vector3d stddev_roll_pitch_yaw_deg = Eigen::Vector3d::Zero();
  Eigen::Vector2d stddev_translation_xy_m = Eigen::Vector2d::Zero();
  double metric_scale = 0.0;  // single segment only, else 0
  double stddev_metric_scale_rel = 0.0;
};

struct RepeatabilityTest {
  std::string name;  // "halves", "quarters"
  int num_blocks = 0;
  bool ran = false;
  std::string reason;  // why not, when it did not run
  std::vector<RepeatabilityBlock> blocks;
  double chi_square = 0.0;
  int dof = 0;
  double p_value = 1.0;
  double alarm_p_value = 0.0;  // the test fails below this
  bool agree = true;
};

struct Repeatability {
  bool ran = false;    // at least one test ran
  std::string reason;  // why none ran
  std::vector<RepeatabilityTest> tests;
  // False when a test that ran failed: the blocks disagree beyond their
  // uncertainty.
  bool consistent = true;
  // When not consistent: the split time whose two sides disagree most,
  // with that test's chi-square and dof.
  std::optional<int64_t> change_stamp_ns;
  double change_chi_square = 0.0;
  int change_dof = 0;
  // The drive's span (the used pairs'), for the change's relative place.
  int64_t first_stamp_ns = 0;
  int64_t last_stamp_ns = 0;
  // The whole drive's estimate the blocks are compared with (metric_scale:
  // single segment only, else 0).
  Rigid3d odom_from_cam;
  double metric_scale = 0.0;
};

// `pairs` and `result` are the final calibration's (CalibrateOdomCam);
// its used pairs (diagnostics.inlier_mask) are blocked, without RANSAC and
// with its noise (result.noise_estimate when estimated). Returns ran =
// false, with the reason, when the result is not a success or no test has
// enough blocks.
Repeatability CheckRepeatability(const MotionPairs& pairs,
                                 const CalibrationResult& result,
                                 const CalibrationOptions& options,
                                 const RepeatabilityOptions& repeatability);

// A p-value as text: three decimals ("0.981", "0.004"), or two significant
// digits below 0.001 ("2.3e-05").
std::string PValueText(double p_value);

// One sentence for the warnings when not consistent, else "".
std::string RepeatabilityWarning(const Repeatability& repeatability);

}  // namespace odomcal
