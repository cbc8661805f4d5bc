#include "odomcal/solver/hand_eye_ransac.h"

#include "odomcal/solver/angles.h"
#include "odomcal/solver/chi_square.h"
#include "odomcal/solver/hand_eye_linear.h"
#include "odomcal/solver/hand_eye_residual.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>

namespace odomcal {
namespace {

constexpr int kSampleSize = 2;
constexpr int kMaxLocalOptimizations = 3;

struct Hypothesis {
  Rigid3d odom_from_cam;
  std::vector<double> metric_scales;
};

LinearOptions ToLinearOptions(const CalibrationOptions& options) {
  LinearOptions linear;
  linear.method = options.method;
  linear.alsp_projection = options.alsp_projection;
  linear.fixed_translation_z_m = options.fixed_translation_z_m;
  return linear;
}

void CompleteScales(const MotionPairs& pairs,
                    const std::vector<int>& indices,
                    int num_segments,
                    Hypothesis* hypothesis) {
  CompleteMetricScales(pairs,
                       indices,
                       num_segments,
                       hypothesis->odom_from_cam,
                       &hypothesis->metric_scales);
}

// Error of a pair relative to the inlier threshold (< 1: inlier), the larger
// of its rotation and translation parts. Each part passes when it is within
// the absolute threshold of the options or within the noise model's 99.9 %
// chi-square bound, so that the thresholds never reject pairs that are only
// as noisy as the model says.
double NormalizedError(const MotionPair& pair,
                       const Rigid3d& odom_from_cam,
                       double metric_scale,
                       const CalibrationOptions& options) {
  static const double kChiSquare3Dof999 = ChiSquare999(3);
  const Vector6d residual = HandEyeResidual(pair, odom_from_cam, metric_scale);
  double rotation = residual.head<3>().norm() * kRadToDeg /
                    options.ransac_max_rotation_error_deg;
  double translation = residual.tail<3>().norm() /
                       (options.ransac_max_translation_error_m +
                        options.ransac_max_translation_error_rel *
                            pair.odom_i_from_odom_j.translation.norm());
  // The covariance is the expensive part: only needed when an absolute
  // threshold fails (then the pair may still be within the noise model).
  if (rotation >= 1.0 || translation >= 1.0) {
    const Matrix6d covariance = HandEyeResidualCovariance(
        pair, odom_from_cam, metric_scale, options.noise);
    if (rotation >= 1.0) {
      rotation =
          std::min(rotation,
                   std::sqrt(residual.head<3>().dot(
                                 covariance.topLeftCorner<3, 3>().ldlt().solve(
                                     residual.head<3>())) /
                             kChiSquare3Dof999));
    }
    if (translation >= 1.0) {
      translation = std::min(
          translation,
          std::sqrt(residual.tail<3>().dot(
                        covariance.bottomRightCorner<3, 3>().ldlt().solve(
                            residual.tail<3>())) /
                    kChiSquare3Dof999));
    }
  }
  return std::max(rotation, translation);
}

// MSAC score (lower is better) and inliers of a hypothesis. The score only
// grows over the pairs: once it reaches `bound` (a score to beat), the
// hypothesis is lost and the rest is not evaluated (score and inliers then
// partial).
double Score(const MotionPairs& pairs,
             const std::vector<int>& indices,
             const Hypothesis& hypothesis,
             const CalibrationOptions& options,
             std::vector<int>* inliers,
             double bound = std::numeric_limits<double>::infinity()) {
  inliers->clear();
  double score = 0.0;
  for (const int index : indices) {
    if (score >= bound) break;
    const MotionPair& pair = pairs[index];
    const double scale = hypothesis.metric_scales[pair.segment];
    if (!(scale > 0.0)) {
      score += 1.0;
      continue;
    }
    const double normalized =
        NormalizedError(pair, hypothesis.odom_from_cam, scale, options);
    if (normalized < 1.0) {
      inliers->push_back(index);
      score += normalized * normalized;
    } else {
      score += 1.0;
    }
  }
  return score;
}

bool FitHypothesis(const MotionPairs& pairs,
                   const std::vector<int>& sample,
                   const std::vector<int>& all,
                   int num_segments,
                   const CalibrationOptions& options,
                   Hypothesis* hypothesis) {
  const LinearEstimate estimate =
      EstimateOdomFromCamLinear(pairs, sample, ToLinearOptions(options));
  if (!estimate.success) return false;
  hypothesis->odom_from_cam = estimate.odom_from_cam;
  hypothesis->metric_scales = estimate.metric_scales;
  CompleteScales(pairs, all, num_segments, hypothesis);
  return true;
}

}  // namespace

void CompleteMetricScales(const MotionPairs& pairs,
                          const std::vector<int>& indices,
                          int num_segments,
                          const Rigid3d& odom_from_cam,
                          std::vector<double>* metric_scales) {
  metric_scales->resize(num_segments, std::numeric_limits<double>::quiet_NaN());
  std::map<int, std::vector<double>> per_segment;
  const Rigid3d& x = odom_from_cam;
  for (const int index : indices) {
    const MotionPair& pair = pairs[index];
    if (std::isfinite((*metric_scales)[pair.segment])) continue;
    // The scale that best fits this pair alone: s = <odom side, cam side> /
    // |cam side|^2 from R_A p + t_A - p = s R t_B.
    const Eigen::Vector3d odom_side =
        pair.odom_i_from_odom_j.rotation * x.translation +
        pair.odom_i_from_odom_j.translation - x.translation;
    const Eigen::Vector3d cam_side =
        x.rotation * pair.cam_i_from_cam_j.translation;
    const double norm2 = cam_side.squaredNorm();
    if (norm2 > 0.0) {
      per_segment[pair.segment].push_back(odom_side.dot(cam_side) / norm2);
    }
  }
  for (auto& [segment, scales] : per_segment) {
    auto middle = scales.begin() + scales.size() / 2;
    std::nth_element(scales.begin(), middle, scales.end());
    (*metric_scales)[segment] = *middle;
  }
}

double RansacScore(const MotionPairs& pairs,
                   const std::vector<int>& indices,
                   const Rigid3d& odom_from_cam,
                   const std::vector<double>& metric_scales,
                   const CalibrationOptions& options,
                   std::vector<int>* inliers) {
  Hypothesis hypothesis;
  hypothesis.odom_from_cam = odom_from_cam;
  hypothesis.metric_scales = metric_scales;
  return Score(pairs, indices, hypothesis, options, inliers);
}

PairError EvaluatePair(const MotionPair& pair,
                       const Rigid3d& odom_from_cam,
                       double metric_scale) {
  const Eigen::Quaterniond& q = odom_from_cam.rotation;
  const Rigid3d& a = pair.odom_i_from_odom_j;
  const Rigid3d& b = pair.cam_i_from_cam_j;
  PairError error;
  error.rotation_deg =
      RotationAngle(a.rotation.conjugate() * q * b.rotation * q.conjugate()) *
      kRadToDeg;
  error.translation_m =
      (a.rotation * odom_from_cam.translation + a.translation -
       metric_scale * (q * b.translation) - odom_from_cam.translation)
          .norm();
  return error;
}

bool IsInlier(const MotionPair& pair,
              const Rigid3d& odom_from_cam,
              double metric_scale,
              const CalibrationOptions& options) {
  return NormalizedError(pair, odom_from_cam, metric_scale, options) < 1.0;
}

RansacResult RansacOdomFromCam(const MotionPairs& pairs,
                               const std::vector<int>& indices,
                               const CalibrationOptions& options) {
  RansacResult result;
  result.inlier_mask.assign(pairs.size(), 0);
  const int num_segments = NumSegments(pairs);
  std::map<int, std::vector<int>> by_segment;
  for (const int index : indices) {
    by_segment[pairs[index].segment].push_back(index);
  }
  std::vector<int> sampleable_segments;
  std::vector<double> segment_weights;
  for (const auto& [segment, members] : by_segment) {
    if (members.size() >= kSampleSize) {
      sampleable_segments.push_back(segment);
      segment_weights.push_back(static_cast<double>(members.size()));
    }
  }
  if (sampleable_segments.empty()) {
    return result;
  }

  std::mt19937_64 rng(options.ransac_seed);
  std::discrete_distribution<int> pick_segment(segment_weights.begin(),
                                               segment_weights.end());
  double best_score = std::numeric_limits<double>::infinity();
  Hypothesis best;
  std::vector<int> best_inliers, inliers;
  int max_iterations = options.ransac_max_iterations;
  int iteration = 0;
  for (; iteration < max_iterations; ++iteration) {
    const std::vector<int>& members =
        by_segment[sampleable_segments[pick_segment(rng)]];
    std::uniform_int_distribution<size_t> pick(0, members.size() - 1);
    const int first = members[pick(rng)];
    int second = first;
    while (second == first) second = members[pick(rng)];
    Hypothesis hypothesis;
    if (!FitHypothesis(pairs,
                       {first, second},
                       indices,
                       num_segments,
                       options,
                       &hypothesis)) {
      continue;
    }
    double score =
        Score(pairs, indices, hypothesis, options, &inliers, best_score);
    if (score >= best_score) continue;

    // Local optimisation: the closed form on all inliers, while it helps.
    for (int lo = 0; lo < kMaxLocalOptimizations &&
                     static_cast<int>(inliers.size()) >= kSampleSize;
         ++lo) {
      Hypothesis refit;
      std::vector<int> refit_inliers;
      if (!FitHypothesis(
              pairs, inliers, indices, num_segments, options, &refit)) {
        break;
      }
      const double refit_score =
          Score(pairs, indices, refit, options, &refit_inliers, score);
      if (refit_score >= score) break;
      hypothesis = refit;
      score = refit_score;
      inliers = refit_inliers;
    }
    best_score = score;
    best = hypothesis;
    best_inliers = inliers;

    const double inlier_ratio =
        static_cast<double>(best_inliers.size()) / indices.size();
    const double all_good = std::pow(inlier_ratio, kSampleSize);
    if (all_good >= 1.0) {
      max_iterations = options.ransac_min_iterations;
    } else if (all_good > 0.0) {
      const double needed =
          std::log(1.0 - options.ransac_confidence) / std::log(1.0 - all_good);
      max_iterations = std::clamp(static_cast<int>(std::ceil(needed)),
                                  options.ransac_min_iterations,
                                  options.ransac_max_iterations);
    }
  }
  result.num_iterations = iteration;
  if (best_inliers.size() < kSampleSize) {
    return result;
  }
  result.success = true;
  result.num_inliers = static_cast<int>(best_inliers.size());
  for (const int index : best_inliers) result.inlier_mask[index] = 1;
  result.odom_from_cam = best.odom_from_cam;
  result.metric_scales = best.metric_scales;
  return result;
}

}  // namespace odomcal
