#include "odomcal/solver/repeatability.h"

#include "odomcal/solver/angles.h"
#include "odomcal/solver/calibrate.h"
#include "odomcal/solver/chi_square.h"
#include "odomcal/solver/format_number.h"
#include "odomcal/solver/noise_estimation.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace odomcal {
namespace {

// The used pairs in time order, their noise already the final calibration's.
struct UsedPairs {
  MotionPairs pairs;
  CalibrationOptions options;
  bool with_scale = false;  // one segment: its scale is compared too
};

UsedPairs PrepareUsedPairs(const MotionPairs& pairs,
                           const CalibrationResult& result,
                           const CalibrationOptions& options) {
  UsedPairs used;
  const std::vector<char>& mask = result.diagnostics.inlier_mask;
  MotionPairs scaled = pairs;
  used.options = options;
  used.options.use_ransac = false;
  used.options.estimate_noise = false;
  if (result.noise_estimate) {
    used.options.noise = result.noise_estimate->noise;
    scaled = ScaleCovariances(pairs, *result.noise_estimate);
  }
  for (size_t k = 0; k < scaled.size(); ++k) {
    if (k < mask.size() && mask[k] != 0) used.pairs.push_back(scaled[k]);
  }
  std::stable_sort(used.pairs.begin(),
                   used.pairs.end(),
                   [](const MotionPair& a, const MotionPair& b) {
                     return a.stamp_i_ns < b.stamp_i_ns;
                   });
  used.with_scale = NumSegments(used.pairs) == 1;
  return used;
}

int64_t Midpoint(const MotionPair& pair) {
  return pair.stamp_i_ns + (pair.stamp_j_ns - pair.stamp_i_ns) / 2;
}

// A block's estimate in the test's coordinates and its covariance.
struct BlockEstimate {
  RepeatabilityBlock block;
  Eigen::VectorXd x;
  Eigen::MatrixXd covariance;
};

BlockEstimate CalibrateBlock(const UsedPairs& used,
                             int64_t begin_ns,
                             int64_t end_ns,
                             bool last,
                             const Rigid3d& reference,
                             const RepeatabilityOptions& repeatability) {
  BlockEstimate estimate;
  RepeatabilityBlock& block = estimate.block;
  MotionPairs pairs;
  int turning = 0;
  for (const MotionPair& pair : used.pairs) {
    const int64_t mid = Midpoint(pair);
    if (mid < begin_ns || (last ? mid > end_ns : mid >= end_ns)) continue;
    pairs.push_back(pair);
    if (RotationAngle(pair.odom_i_from_odom_j.rotation) * kRadToDeg >=
        used.options.min_rotation_deg) {
      ++turning;
    }
  }
  block.num_pairs = static_cast<int>(pairs.size());
  if (pairs.empty()) {
    block.first_stamp_ns = begin_ns;
    block.last_stamp_ns = end_ns;
    block.reason = "no pairs";
    return estimate;
  }
  block.first_stamp_ns = pairs.front().stamp_i_ns;
  block.last_stamp_ns = pairs.back().stamp_j_ns;
  if (block.num_pairs < repeatability.min_pairs_per_block ||
      turning < repeatability.min_turning_pairs_per_block) {
    block.reason = std::to_string(block.num_pairs) + " pairs, " +
                   std::to_string(turning) + " turning: fewer than " +
                   std::to_string(repeatability.min_pairs_per_block) + " or " +
                   std::to_string(repeatability.min_turning_pairs_per_block);
    return estimate;
  }
  const CalibrationResult result = CalibrateOdomCam(pairs, used.options);
  const bool scale_row = used.with_scale && result.covariance &&
                         result.covariance_segments.size() == 1;
  if (!result.IsSuccess() || !result.covariance ||
      (used.with_scale && !scale_row)) {
    block.reason = "not calibrated on its own: " + result.message;
    return estimate;
  }
  block.calibrated = true;
  block.odom_from_cam = result.odom_from_cam;
  block.roll_pitch_yaw_deg =
      RollPitchYaw(result.odom_from_cam.rotation) * kRadToDeg;
  block.stddev_roll_pitch_yaw_deg = result.stddev_roll_pitch_yaw_deg;
  block.stddev_translation_xy_m = result.stddev_translation_xy_m;
  const int p = used.with_scale ? 6 : 5;
  estimate.x.resize(p);
  estimate.x.head<3>() = LogRotation(result.odom_from_cam.rotation *
                                     reference.rotation.conjugate());
  estimate.x.segment<2>(3) = result.odom_from_cam.translation.head<2>();
  estimate.covariance = result.covariance->topLeftCorner(p, p);
  if (used.with_scale) {
    block.metric_scale = result.metric_scales[0];
    block.stddev_metric_scale_rel = result.stddev_metric_scales_rel.empty()
                                        ? 0.0
                                        : result.stddev_metric_scales_rel[0];
    estimate.x(5) = result.metric_scales[0];
  }
  return estimate;
}

// The chi-square of the blocks' agreement; false when a covariance is not
// positive definite.
bool AgreementChiSquare(const std::vector<BlockEstimate>& blocks,
                        double* chi_square) {
  const Eigen::Index p = blocks.front().x.size();
  Eigen::MatrixXd information_sum = Eigen::MatrixXd::Zero(p, p);
  Eigen::VectorXd weighted_sum = Eigen::VectorXd::Zero(p);
  std::vector<Eigen::MatrixXd> information;
  for (const BlockEstimate& block : blocks) {
    const Eigen::LLT<Eigen::MatrixXd> llt(block.covariance);
    if (llt.info() != Eigen::Success) return false;
    information.push_back(llt.solve(Eigen::MatrixXd::Identity(p, p)));
    information_sum += information.back();
    weighted_sum += information.back() * block.x;
  }
  const Eigen::VectorXd mean = information_sum.ldlt().solve(weighted_sum);
  *chi_square = 0.0;
  for (size_t k = 0; k < blocks.size(); ++k) {
    const Eigen::VectorXd d = blocks[k].x - mean;
    *chi_square += d.dot(information[k] * d);
  }
  return std::isfinite(*chi_square);
}

// Blocks between `cuts` (ascending times, first and last the span's ends).
std::vector<BlockEstimate> CalibrateBlocks(
    const UsedPairs& used,
    const std::vector<int64_t>& cuts,
    const Rigid3d& reference,
    const RepeatabilityOptions& repeatability) {
  std::vector<BlockEstimate> blocks;
  for (size_t k = 0; k + 1 < cuts.size(); ++k) {
    blocks.push_back(CalibrateBlock(used,
                                    cuts[k],
                                    cuts[k + 1],
                                    k + 2 == cuts.size(),
                                    reference,
                                    repeatability));
  }
  return blocks;
}

std::vector<int64_t> EvenCuts(int64_t first_ns, int64_t last_ns, int count) {
  std::vector<int64_t> cuts;
  const double span = static_cast<double>(last_ns - first_ns);
  for (int k = 0; k <= count; ++k) {
    cuts.push_back(first_ns + static_cast<int64_t>(std::llround(
                                  span * static_cast<double>(k) / count)));
  }
  return cuts;
}

RepeatabilityTest RunTest(const std::string& name,
                          int num_blocks,
                          double alarm_p_value,
                          const UsedPairs& used,
                          int64_t first_ns,
                          int64_t last_ns,
                          const Rigid3d& reference,
                          const RepeatabilityOptions& repeatability) {
  RepeatabilityTest test;
  test.name = name;
  test.num_blocks = num_blocks;
  test.alarm_p_value = alarm_p_value;
  const std::vector<BlockEstimate> blocks = CalibrateBlocks(
      used, EvenCuts(first_ns, last_ns, num_blocks), reference, repeatability);
  for (const BlockEstimate& block : blocks) {
    test.blocks.push_back(block.block);
    if (!block.block.calibrated && test.reason.empty()) {
      test.reason = "block " + std::to_string(test.blocks.size()) + ": " +
                    block.block.reason;
    }
  }
  if (!test.reason.empty()) return test;
  if (!AgreementChiSquare(blocks, &test.chi_square)) {
    test.reason = "a block's covariance is not positive definite";
    return test;
  }
  test.ran = true;
  test.dof = (num_blocks - 1) * static_cast<int>(blocks.front().x.size());
  test.p_value = ChiSquareUpperTail(test.chi_square, test.dof);
  test.agree = test.p_value >= alarm_p_value;
  return test;
}

}  // namespace

void RepeatabilityOptions::Check() const {
  if (!(alarm_probability > 0.0 && alarm_probability < 1.0)) {
    throw std::invalid_argument("alarm_probability must be in (0, 1), got " +
                                FormatNumber(alarm_probability));
  }
  if (min_pairs_per_block < 2 || min_turning_pairs_per_block < 1) {
    throw std::invalid_argument(
        "min_pairs_per_block must be >= 2 and min_turning_pairs_per_block "
        ">= 1");
  }
  if (num_split_times < 1) {
    throw std::invalid_argument("num_split_times must be >= 1, got " +
                                std::to_string(num_split_times));
  }
}

Repeatability CheckRepeatability(const MotionPairs& pairs,
                                 const CalibrationResult& result,
                                 const CalibrationOptions& options,
                                 const RepeatabilityOptions& repeatability) {
  repeatability.Check();
  Repeatability out;
  if (!result.IsSuccess()) {
    out.reason = "the calibration did not succeed";
    return out;
  }
  const UsedPairs used = PrepareUsedPairs(pairs, result, options);
  if (used.pairs.size() < 2) {
    out.reason = "too few pairs";
    return out;
  }
  int64_t first_ns = used.pairs.front().stamp_i_ns;
  int64_t last_ns = first_ns;
  for (const MotionPair& pair : used.pairs) {
    first_ns = std::min(first_ns, Midpoint(pair));
    last_ns = std::max(last_ns, Midpoint(pair));
  }
  out.first_stamp_ns = used.pairs.front().stamp_i_ns;
  out.last_stamp_ns = used.pairs.back().stamp_j_ns;
  out.odom_from_cam = result.odom_from_cam;
  if (used.with_scale && !result.metric_scales.empty()) {
    out.metric_scale = result.metric_scales[0];
  }
  const Rigid3d& reference = result.odom_from_cam;
  const double alarm = 0.5 * repeatability.alarm_probability;
  out.tests.push_back(RunTest(
      "halves", 2, alarm, used, first_ns, last_ns, reference, repeatability));
  out.tests.push_back(RunTest(
      "quarters", 4, alarm, used, first_ns, last_ns, reference, repeatability));
  for (const RepeatabilityTest& test : out.tests) {
    out.ran = out.ran || test.ran;
    if (test.ran && !test.agree) out.consistent = false;
  }
  if (!out.ran) {
    out.reason = "the halves: " + out.tests[0].reason;
    return out;
  }
  if (out.consistent) return out;

  // Name the time of the change: the split whose sides disagree most.
  const double span = static_cast<double>(last_ns - first_ns);
  const int n = repeatability.num_split_times;
  for (int k = 0; k < n; ++k) {
    const double fraction = 0.1 + 0.8 * (n == 1 ? 0.5 : k / (n - 1.0));
    const int64_t split =
        first_ns + static_cast<int64_t>(std::llround(fraction * span));
    const std::vector<BlockEstimate> sides = CalibrateBlocks(
        used, {first_ns, split, last_ns}, reference, repeatability);
    if (!sides[0].block.calibrated || !sides[1].block.calibrated) continue;
    double chi_square = 0.0;
    if (!AgreementChiSquare(sides, &chi_square)) continue;
    if (!out.change_stamp_ns || chi_square > out.change_chi_square) {
      out.change_stamp_ns = split;
      out.change_chi_square = chi_square;
      out.change_dof = static_cast<int>(sides[0].x.size());
    }
  }
  return out;
}

std::string PValueText(double p_value) {
  return p_value < 0.001 ? FormatRounded(p_value, 2)
                         : FormatPrintf("%.3f", p_value);
}

std::string RepeatabilityWarning(const Repeatability& repeatability) {
  if (!repeatability.ran || repeatability.consistent) return "";
  std::string text = "the calibration does not repeat:";
  for (const RepeatabilityTest& test : repeatability.tests) {
    if (!test.ran || test.agree) continue;
    text += " the " + test.name + " of the drive disagree beyond their " +
            "uncertainty (chi-square " + FormatRounded(test.chi_square) +
            " on " + std::to_string(test.dof) + " dof, p " +
            PValueText(test.p_value) + ");";
  }
  if (repeatability.change_stamp_ns) {
    const double after_s = static_cast<double>(*repeatability.change_stamp_ns -
                                               repeatability.first_stamp_ns) *
                           1e-9;
    text += " the camera mount may have moved about " + FormatRounded(after_s) +
            " s after the first pair (the split whose sides disagree most);";
  }
  text +=
      " the result is an average over a changing extrinsic: calibrate the "
      "parts apart, or check the mount";
  return text;
}

}  // namespace odomcal
