#include "odomcal/datasets/paper/chang_baseline.h"

#include "odomcal/solver/angles.h"
#include "odomcal/solver/hand_eye_linear.h"
#include "odomcal/solver/hand_eye_ransac.h"

#include <cmath>
#include <limits>
#include <map>
#include <random>

namespace odomcal {
namespace {

constexpr double kMinAxisRotationRad = 1e-6;

}  // namespace

bool SolveChangMinimal(const MotionPair& axis_pair,
                       const MotionPair& first,
                       const MotionPair& second,
                       double fixed_translation_z_m,
                       Rigid3d* odom_from_cam,
                       double* metric_scale) {
  const Eigen::Vector3d camera_axis_angle =
      LogRotation(axis_pair.cam_i_from_cam_j.rotation);
  const double yaw = LogRotation(axis_pair.odom_i_from_odom_j.rotation).z();
  if (camera_axis_angle.norm() < kMinAxisRotationRad ||
      std::abs(yaw) < kMinAxisRotationRad) {
    return false;
  }
  const Eigen::Vector3d target =
      (yaw > 0.0 ? 1.0 : -1.0) * Eigen::Vector3d::UnitZ();
  const Eigen::Quaterniond q_yz = Eigen::Quaterniond::FromTwoVectors(
      camera_axis_angle.normalized(), target);

  MotionPairs two = {first, second};
  two[0].segment = two[1].segment = 0;
  LinearOptions linear;
  linear.method = LinearMethod::kAls;
  linear.fixed_translation_z_m = fixed_translation_z_m;
  LinearEstimate estimate;
  if (!SolveYawTranslationScale(two, {0, 1}, q_yz, linear, &estimate) ||
      !(estimate.metric_scales[0] > 0.0)) {
    return false;
  }
  *odom_from_cam = estimate.odom_from_cam;
  *metric_scale = estimate.metric_scales[0];
  return true;
}

ChangEstimate EstimateOdomFromCamChang(const MotionPairs& pairs,
                                       const CalibrationOptions& options) {
  ChangEstimate result;
  result.inlier_mask.assign(pairs.size(), 0);
  const int num_segments = NumSegments(pairs);
  std::vector<int> all(pairs.size());
  std::vector<int> rotating;
  std::map<int, std::vector<int>> by_segment;
  for (size_t i = 0; i < pairs.size(); ++i) {
    all[i] = static_cast<int>(i);
    by_segment[pairs[i].segment].push_back(static_cast<int>(i));
    if (std::abs(LogRotation(pairs[i].odom_i_from_odom_j.rotation).z()) >=
        options.min_rotation_deg * kPi / 180.0) {
      rotating.push_back(static_cast<int>(i));
    }
  }
  std::vector<int> segments;
  for (const auto& [segment, members] : by_segment) {
    if (members.size() >= 2) segments.push_back(segment);
  }
  if (rotating.empty() || segments.empty()) {
    result.failure = "CM needs a rotating motion and two motions of a segment";
    return result;
  }

  std::mt19937_64 rng(options.ransac_seed);
  std::uniform_int_distribution<size_t> pick_rotating(0, rotating.size() - 1);
  std::uniform_int_distribution<size_t> pick_segment(0, segments.size() - 1);
  double best_score = std::numeric_limits<double>::infinity();
  std::vector<int> inliers;
  // A fixed budget: the sample size of three makes adaptive stopping
  // pessimistic, and the baseline should not cost more than the method.
  const int iterations = options.ransac_max_iterations;
  for (int iteration = 0; iteration < iterations; ++iteration) {
    ++result.num_iterations;
    const std::vector<int>& members = by_segment[segments[pick_segment(rng)]];
    std::uniform_int_distribution<size_t> pick(0, members.size() - 1);
    const int axis = rotating[pick_rotating(rng)];
    const int first = members[pick(rng)];
    int second = first;
    while (second == first) second = members[pick(rng)];
    Rigid3d odom_from_cam;
    double scale = 0.0;
    if (!SolveChangMinimal(pairs[axis],
                           pairs[first],
                           pairs[second],
                           options.fixed_translation_z_m,
                           &odom_from_cam,
                           &scale)) {
      continue;
    }
    std::vector<double> scales(num_segments,
                               std::numeric_limits<double>::quiet_NaN());
    scales[pairs[first].segment] = scale;
    CompleteMetricScales(pairs, all, num_segments, odom_from_cam, &scales);
    const double score =
        RansacScore(pairs, all, odom_from_cam, scales, options, &inliers);
    if (score < best_score) {
      best_score = score;
      result.success = true;
      result.odom_from_cam = odom_from_cam;
      result.metric_scales = scales;
      result.inlier_mask.assign(pairs.size(), 0);
      for (const int i : inliers) result.inlier_mask[i] = 1;
    }
  }
  if (!result.success) {
    result.failure = "no CM hypothesis could be formed";
  }
  return result;
}

}  // namespace odomcal
