#include "odomcal/solver/scale_consistency.h"

#include "odomcal/solver/f_distribution.h"
#include "odomcal/solver/hand_eye_residual.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace odomcal {
namespace {

// Weighted sums of one run of per-pair scales a_i (centred), their
// regressors r_i = (lever arm gradient g_i, time tau_i) and weights
// w_i = 1 / sigma_i^2, for the linear model
//   a_i = s_part(i) + g_i . theta [+ slope tau_i]
// (theta: lever arm x/y and slope shared by the parts fitted together).
struct Sums {
  double w = 0.0, wa = 0.0, waa = 0.0;
  Eigen::Vector3d wr = Eigen::Vector3d::Zero();
  Eigen::Vector3d war = Eigen::Vector3d::Zero();
  Eigen::Matrix3d wrr = Eigen::Matrix3d::Zero();

  Sums operator-(const Sums& other) const {
    Sums d;
    d.w = w - other.w;
    d.wa = wa - other.wa;
    d.waa = waa - other.waa;
    d.wr = wr - other.wr;
    d.war = war - other.war;
    d.wrr = wrr - other.wrr;
    return d;
  }
};

// Fit of one partition: chi-square, rank of the normal equations (number of
// determined parameters) and the part scales.
struct PartitionFit {
  double chi_square = 0.0;
  int rank = 0;
  std::vector<double> scales;  // centred, like the a_i
  double slope = 0.0;          // per second, with a trend
};

class PrefixSums {
 public:
  PrefixSums(const std::vector<PairMetricScale>& values,
             const std::vector<double>& times_s,
             double centre)
      : sums_(values.size() + 1) {
    for (size_t i = 0; i < values.size(); ++i) {
      const double w = 1.0 / (values[i].stddev * values[i].stddev);
      const double a = values[i].scale - centre;
      Eigen::Vector3d r;
      r << values[i].scale_per_lever_arm_xy, times_s[i];
      Sums& next = sums_[i + 1];
      next = sums_[i];
      next.w += w;
      next.wa += w * a;
      next.waa += w * a * a;
      next.wr += w * r;
      next.war += w * a * r;
      next.wrr += w * r * r.transpose();
    }
  }

  // Parts [bounds[k], bounds[k + 1]) with a scale each, one lever arm, and
  // with `trend` one slope over time.
  PartitionFit Fit(const std::vector<int>& bounds, bool trend = false) const {
    const int num_parts = static_cast<int>(bounds.size()) - 1;
    const int m = trend ? 3 : 2;  // shared regressors
    const int n = m + num_parts;
    Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
    double waa = 0.0;
    for (int k = 0; k < num_parts; ++k) {
      const Sums part = sums_[bounds[k + 1]] - sums_[bounds[k]];
      normal.topLeftCorner(m, m) += part.wrr.topLeftCorner(m, m);
      normal.block(0, m + k, m, 1) = part.wr.head(m);
      normal.block(m + k, 0, 1, m) = part.wr.head(m).transpose();
      normal(m + k, m + k) = part.w;
      rhs.head(m) += part.war.head(m);
      rhs(m + k) = part.wa;
      waa += part.waa;
    }
    // Pseudo-inverse of the diagonally normalised system: a lever arm the
    // pairs do not determine (no turns) drops out instead of failing.
    Eigen::VectorXd inv_sqrt(n);
    for (int k = 0; k < n; ++k) {
      inv_sqrt(k) = normal(k, k) > 0.0 ? 1.0 / std::sqrt(normal(k, k)) : 0.0;
    }
    const Eigen::MatrixXd scaled =
        inv_sqrt.asDiagonal() * normal * inv_sqrt.asDiagonal();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(scaled);
    const double largest = eig.eigenvalues().maxCoeff();
    const Eigen::VectorXd scaled_rhs = inv_sqrt.asDiagonal() * rhs;
    const Eigen::VectorXd projected =
        eig.eigenvectors().transpose() * scaled_rhs;
    Eigen::VectorXd solution_in_eigenbasis = Eigen::VectorXd::Zero(n);
    PartitionFit fit;
    double explained = 0.0;
    for (int k = 0; k < n; ++k) {
      if (!(eig.eigenvalues()(k) > 1e-10 * largest)) continue;
      ++fit.rank;
      solution_in_eigenbasis(k) = projected(k) / eig.eigenvalues()(k);
      explained += projected(k) * solution_in_eigenbasis(k);
    }
    const Eigen::VectorXd solution =
        inv_sqrt.asDiagonal() * (eig.eigenvectors() * solution_in_eigenbasis);
    fit.chi_square = std::max(0.0, waa - explained);
    for (int k = 0; k < num_parts; ++k) fit.scales.push_back(solution(m + k));
    if (trend) fit.slope = solution(2);
    return fit;
  }

 private:
  std::vector<Sums> sums_;
};

// F statistic of a nested model: the drop of chi-square per added parameter
// against the larger model's scatter per degree of freedom, and its
// critical value at `probability`. Not a test (threshold infinite) when the
// larger model determines nothing more or leaves no degree of freedom.
struct FTest {
  double f_statistic = 0.0;
  double f_threshold = std::numeric_limits<double>::infinity();
  bool Significant() const { return f_statistic > f_threshold; }
};

FTest NestedFTest(const PartitionFit& smaller,
                  const PartitionFit& larger,
                  int num_values,
                  double probability) {
  FTest test;
  const int added = larger.rank - smaller.rank;
  const int dof = num_values - larger.rank;
  if (added <= 0 || dof <= 0) return test;
  const double noise = larger.chi_square / dof;
  const double drop = (smaller.chi_square - larger.chi_square) / added;
  test.f_statistic =
      noise > 0.0
          ? drop / noise
          : (drop > 0.0 ? std::numeric_limits<double>::infinity() : 0.0);
  test.f_threshold = FDistributionCriticalValue(probability, added, dof);
  return test;
}

struct Split {
  int at = -1;  // first index of the second part
  FTest step;   // two constant parts against one
  FTest trend;  // one part with a linear trend against a constant
  double scale_before = 0.0, scale_after = 0.0;  // centred
  double trend_change = 0.0;  // slope times the duration (centred units)
};

// The best split of [begin, end) into two constant parts and the F-tests
// of a step there and of a linear trend over [begin, end). Half the
// false-cut probability goes to each; the step's half is divided among the
// split points searched (Bonferroni).
Split BestSplit(const PrefixSums& sums,
                const std::vector<double>& times_s,
                int begin,
                int end,
                const ScaleChangeOptions& options) {
  Split best;
  const int n = end - begin;
  const int min_part = std::max(1, options.min_pairs_per_part);
  if (n < 2 * min_part) return best;
  const PartitionFit one = sums.Fit({begin, end});
  PartitionFit best_two;
  best_two.chi_square = std::numeric_limits<double>::infinity();
  for (int at = begin + min_part; at <= end - min_part; ++at) {
    PartitionFit two = sums.Fit({begin, at, end});
    if (two.chi_square < best_two.chi_square) {
      best_two = std::move(two);
      best.at = at;
    }
  }
  if (best.at < 0) return best;
  const int num_splits = n - 2 * min_part + 1;
  best.step = NestedFTest(
      one, best_two, n, 0.5 * options.false_cut_probability / num_splits);
  const PartitionFit trend = sums.Fit({begin, end}, /*trend=*/true);
  best.trend = NestedFTest(one, trend, n, 0.5 * options.false_cut_probability);
  best.scale_before = best_two.scales[0];
  best.scale_after = best_two.scales[1];
  best.trend_change = trend.slope * (times_s[end - 1] - times_s[begin]);
  return best;
}

struct Cut {
  int at = 0;
  double f_statistic = 0.0;
  double f_threshold = 0.0;
};

// Binary segmentation of values[begin, end); cuts are indices into values.
// A part is cut where a step is significant, or, failing that, where its
// linear trend is (a drift, as incremental SfM's, that no single step
// explains well), at the best split point.
void Segment(const PrefixSums& sums,
             const std::vector<double>& times_s,
             int begin,
             int end,
             double centre,
             const ScaleChangeOptions& options,
             std::vector<Cut>* cuts) {
  if (static_cast<int>(cuts->size()) >= options.max_changes_per_segment) return;
  const Split split = BestSplit(sums, times_s, begin, end, options);
  if (split.at < 0) return;
  const double before = split.scale_before + centre;
  const double after = split.scale_after + centre;
  const double smaller = std::min(std::abs(before), std::abs(after));
  const bool step =
      split.step.Significant() &&
      std::abs(after - before) >= options.min_relative_change * smaller;
  const bool trend =
      split.trend.Significant() &&
      std::abs(split.trend_change) >= options.min_relative_change * smaller;
  if (!step && !trend) return;
  const FTest& test = step ? split.step : split.trend;
  cuts->push_back({split.at, test.f_statistic, test.f_threshold});
  Segment(sums, times_s, begin, split.at, centre, options, cuts);
  Segment(sums, times_s, split.at, end, centre, options, cuts);
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
    const Eigen::Matrix3d r_a_minus_i =
        pair.odom_i_from_odom_j.rotation.toRotationMatrix() -
        Eigen::Matrix3d::Identity();
    const Eigen::Vector3d d =
        r_a_minus_i * p + pair.odom_i_from_odom_j.translation;
    const Eigen::Vector3d u = R * pair.cam_i_from_cam_j.translation;
    const Eigen::Matrix3d cov =
        HandEyeResidualCovariance(pair, odom_from_cam, s, noise)
            .bottomRightCorner<3, 3>();
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(cov);
    const Eigen::Vector3d w_u = ldlt.solve(u);
    const double information = u.dot(w_u);
    if (ldlt.info() != Eigen::Success || !(information > 0.0) ||
        !std::isfinite(information)) {
      result[i].scale = s;
      result[i].stddev = std::numeric_limits<double>::infinity();
      continue;
    }
    result[i].scale = w_u.dot(d) / information;
    result[i].stddev = 1.0 / std::sqrt(information);
    result[i].scale_per_lever_arm_xy =
        (r_a_minus_i.transpose() * w_u).head<2>() / information;
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
        value.stddev > 0.0 && value.scale_per_lever_arm_xy.allFinite()) {
      members[pairs[i].segment].push_back(static_cast<int>(i));
    }
  }
  std::vector<ScaleChange> changes;
  for (auto& [segment, indices] : members) {
    std::stable_sort(indices.begin(), indices.end(), [&](int a, int b) {
      return pairs[a].stamp_i_ns < pairs[b].stamp_i_ns;
    });
    std::vector<PairMetricScale> values;
    std::vector<double> times_s;  // pair mid times from the first
    double sum_w = 0.0, sum_ws = 0.0;
    for (const int i : indices) {
      values.push_back(pair_scales[i]);
      times_s.push_back(
          0.5e-9 * static_cast<double>(
                       (pairs[i].stamp_i_ns - pairs[indices[0]].stamp_i_ns) +
                       (pairs[i].stamp_j_ns - pairs[indices[0]].stamp_i_ns)));
      const double w = 1.0 / (pair_scales[i].stddev * pair_scales[i].stddev);
      sum_w += w;
      sum_ws += w * pair_scales[i].scale;
    }
    const double centre = sum_ws / sum_w;  // keeps the sums well conditioned
    const PrefixSums sums(values, times_s, centre);
    std::vector<Cut> cuts;
    Segment(sums,
            times_s,
            0,
            static_cast<int>(values.size()),
            centre,
            options,
            &cuts);
    if (cuts.empty()) continue;
    std::sort(cuts.begin(), cuts.end(), [](const Cut& a, const Cut& b) {
      return a.at < b.at;
    });
    // Part scales from one joint fit of all parts and the lever arm.
    std::vector<int> bounds = {0};
    for (const Cut& cut : cuts) bounds.push_back(cut.at);
    bounds.push_back(static_cast<int>(values.size()));
    const PartitionFit fit = sums.Fit(bounds);
    for (size_t c = 0; c < cuts.size(); ++c) {
      ScaleChange change;
      change.segment = segment;
      change.first_pair_after = indices[cuts[c].at];
      change.stamp_ns = pairs[change.first_pair_after].stamp_i_ns;
      change.scale_before = fit.scales[c] + centre;
      change.scale_after = fit.scales[c + 1] + centre;
      change.f_statistic = cuts[c].f_statistic;
      change.f_threshold = cuts[c].f_threshold;
      changes.push_back(change);
    }
  }
  return changes;
}

}  // namespace odomcal
