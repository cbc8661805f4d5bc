#include "odomcal/solver/scale_consistency.h"

#include "odomcal/solver/hand_eye_residual.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace odomcal {
namespace {

// Weighted sums over a run of per-pair scales: mean and chi-square in O(1)
// from prefix sums.
struct PrefixSums {
  std::vector<double> w, ws, wss;  // size n + 1

  explicit PrefixSums(const std::vector<PairMetricScale>& values)
      : w(values.size() + 1, 0.0),
        ws(values.size() + 1, 0.0),
        wss(values.size() + 1, 0.0) {
    for (size_t i = 0; i < values.size(); ++i) {
      const double weight = 1.0 / (values[i].stddev * values[i].stddev);
      w[i + 1] = w[i] + weight;
      ws[i + 1] = ws[i] + weight * values[i].scale;
      wss[i + 1] = wss[i] + weight * values[i].scale * values[i].scale;
    }
  }
  double Mean(int begin, int end) const {
    return (ws[end] - ws[begin]) / (w[end] - w[begin]);
  }
  double ChiSquare(int begin, int end) const {
    const double sw = w[end] - w[begin];
    const double sws = ws[end] - ws[begin];
    return std::max(0.0, (wss[end] - wss[begin]) - sws * sws / sw);
  }
};

struct Split {
  int at = -1;  // first index of the second part
  double f_statistic = 0.0;
};

Split BestSplit(const PrefixSums& sums, int begin, int end, int min_part) {
  Split best;
  const int n = end - begin;
  if (n < 2 * min_part) return best;
  const double chi_one = sums.ChiSquare(begin, end);
  double best_chi_two = std::numeric_limits<double>::infinity();
  for (int at = begin + min_part; at <= end - min_part; ++at) {
    const double chi_two = sums.ChiSquare(begin, at) + sums.ChiSquare(at, end);
    if (chi_two < best_chi_two) {
      best_chi_two = chi_two;
      best.at = at;
    }
  }
  const double noise = best_chi_two / (n - 2);
  const double drop = chi_one - best_chi_two;
  best.f_statistic =
      noise > 0.0
          ? drop / noise
          : (drop > 0.0 ? std::numeric_limits<double>::infinity() : 0.0);
  return best;
}

// Binary segmentation of values[begin, end); cuts are indices into values.
void Segment(const PrefixSums& sums,
             int begin,
             int end,
             const ScaleChangeOptions& options,
             std::vector<std::pair<int, double>>* cuts) {
  if (static_cast<int>(cuts->size()) >= options.max_changes_per_segment) return;
  const Split split = BestSplit(sums, begin, end, options.min_pairs_per_part);
  if (split.at < 0 || !(split.f_statistic >= options.min_f_statistic)) return;
  const double before = sums.Mean(begin, split.at);
  const double after = sums.Mean(split.at, end);
  const double relative =
      std::abs(after - before) / std::min(std::abs(before), std::abs(after));
  if (!(relative >= options.min_relative_change)) return;
  cuts->emplace_back(split.at, split.f_statistic);
  Segment(sums, begin, split.at, options, cuts);
  Segment(sums, split.at, end, options, cuts);
}

}  // namespace

std::vector<PairMetricScale> PerPairMetricScales(
    const MotionPairs& pairs,
    const Rigid3d& odom_from_cam,
    const std::vector<double>& metric_scales,
    const NoiseModel& noise) {
  std::vector<PairMetricScale> result(pairs.size());
  const Eigen::Matrix3d R = odom_from_cam.rotation.toRotationMatrix();
  const Eigen::Vector3d& p = odom_from_cam.translation;
  for (size_t i = 0; i < pairs.size(); ++i) {
    const MotionPair& pair = pairs[i];
    const double s = metric_scales.at(pair.segment);
    const Eigen::Vector3d d = pair.odom_i_from_odom_j.rotation * p +
                              pair.odom_i_from_odom_j.translation - p;
    const Eigen::Vector3d u = R * pair.cam_i_from_cam_j.translation;
    const Eigen::Matrix3d cov =
        HandEyeResidualCovariance(pair, odom_from_cam, s, noise)
            .bottomRightCorner<3, 3>();
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(cov);
    const Eigen::Vector3d w_u = ldlt.solve(u);
    const double information = u.dot(w_u);
    if (ldlt.info() != Eigen::Success || !(information > 0.0) ||
        !std::isfinite(information)) {
      result[i] = {s, std::numeric_limits<double>::infinity()};
      continue;
    }
    result[i] = {w_u.dot(d) / information, 1.0 / std::sqrt(information)};
  }
  return result;
}

std::vector<ScaleChange> FindScaleChanges(
    const MotionPairs& pairs,
    const std::vector<PairMetricScale>& pair_scales,
    const ScaleChangeOptions& options) {
  std::map<int, std::vector<int>>
      members;  // usable pairs per segment, in time order
  for (size_t i = 0; i < pairs.size(); ++i) {
    const PairMetricScale& value = pair_scales.at(i);
    if (std::isfinite(value.scale) && std::isfinite(value.stddev) &&
        value.stddev > 0.0) {
      members[pairs[i].segment].push_back(static_cast<int>(i));
    }
  }
  std::vector<ScaleChange> changes;
  for (auto& [segment, indices] : members) {
    std::stable_sort(indices.begin(), indices.end(), [&](int a, int b) {
      return pairs[a].stamp_i_ns < pairs[b].stamp_i_ns;
    });
    std::vector<PairMetricScale> values;
    for (const int i : indices) values.push_back(pair_scales[i]);
    const PrefixSums sums(values);
    std::vector<std::pair<int, double>> cuts;
    Segment(sums, 0, static_cast<int>(values.size()), options, &cuts);
    std::sort(cuts.begin(), cuts.end());
    for (size_t c = 0; c < cuts.size(); ++c) {
      const int begin = c == 0 ? 0 : cuts[c - 1].first;
      const int end = c + 1 < cuts.size() ? cuts[c + 1].first
                                          : static_cast<int>(values.size());
      ScaleChange change;
      change.segment = segment;
      change.first_pair_after = indices[cuts[c].first];
      change.stamp_ns = pairs[change.first_pair_after].stamp_i_ns;
      change.scale_before = sums.Mean(begin, cuts[c].first);
      change.scale_after = sums.Mean(cuts[c].first, end);
      change.f_statistic = cuts[c].second;
      changes.push_back(change);
    }
  }
  return changes;
}

}  // namespace odomcal
