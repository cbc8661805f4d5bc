#include "odomcal/solver/scale_drift_covariance.h"

#include "odomcal/solver/angles.h"
#include "odomcal/solver/covariance_analysis_internal.h"
#include "odomcal/solver/format_number.h"
#include "odomcal/solver/hand_eye_refine.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

namespace odomcal {
namespace {

// One used pair of a segment: its mid time (s, from the segment's first),
// relative scale and that's first-order variance.
struct Observation {
  int index = 0;  // into the used list
  double time_s = 0.0;
  double value = 0.0;
  double variance = 0.0;
};

double MidTimeSeconds(const MotionPair& pair) {
  return 0.5 * 1e-9 *
         (static_cast<double>(pair.stamp_i_ns) +
          static_cast<double>(pair.stamp_j_ns));
}

// Used pairs per segment, in time order, times from the segment's first
// pair; only pairs with a finite scale and variance when `scales` is given.
std::vector<std::vector<Observation>> SegmentSeries(
    const MotionPairs& pairs,
    const std::vector<int>& used,
    const std::vector<PairMetricScale>* scales,
    const std::vector<double>* metric_scales) {
  std::map<int, std::vector<Observation>> by_segment;
  for (size_t u = 0; u < used.size(); ++u) {
    const MotionPair& pair = pairs[used[u]];
    Observation observation;
    observation.index = static_cast<int>(u);
    observation.time_s = MidTimeSeconds(pair);
    if (scales != nullptr) {
      const PairMetricScale& scale = (*scales)[used[u]];
      const double level =
          pair.segment >= 0 &&
                  static_cast<size_t>(pair.segment) < metric_scales->size()
              ? (*metric_scales)[pair.segment]
              : 0.0;
      if (!(level > 0.0) || !std::isfinite(scale.scale) ||
          !std::isfinite(scale.stddev) || !(scale.stddev > 0.0)) {
        continue;
      }
      observation.value = scale.scale / level - 1.0;
      observation.variance = std::pow(scale.stddev / level, 2);
    }
    by_segment[pair.segment].push_back(observation);
  }
  std::vector<std::vector<Observation>> series;
  for (auto& [segment, observations] : by_segment) {
    std::stable_sort(observations.begin(),
                     observations.end(),
                     [](const Observation& a, const Observation& b) {
                       return a.time_s < b.time_s;
                     });
    const double start = observations.front().time_s;
    for (Observation& observation : observations) observation.time_s -= start;
    series.push_back(std::move(observations));
  }
  return series;
}

// The local-level model's Kalman filter over every series with the random
// walk's rate r in units of the scatter factor c (all variances over c).
struct FilterSums {
  double weighted_squares = 0.0;  // sum e^2 / F
  double log_variances = 0.0;     // sum log F
  int num_innovations = 0;

  // Log-likelihood with c concentrated out (constants dropped).
  double ProfileLogLikelihood() const {
    if (num_innovations == 0 || !(weighted_squares > 0.0)) return 0.0;
    const double c = weighted_squares / num_innovations;
    return -0.5 * (num_innovations * std::log(c) + log_variances);
  }
};

FilterSums Filter(const std::vector<std::vector<Observation>>& series,
                  double rate) {
  FilterSums sums;
  for (const std::vector<Observation>& observations : series) {
    if (observations.size() < 3) continue;
    // Diffuse start: the first pair fixes the level.
    double level = observations[0].value;
    double variance = observations[0].variance;
    for (size_t t = 1; t < observations.size(); ++t) {
      const Observation& o = observations[t];
      const double predicted =
          variance + rate * (o.time_s - observations[t - 1].time_s);
      const double innovation_variance = predicted + o.variance;
      const double innovation = o.value - level;
      sums.weighted_squares += innovation * innovation / innovation_variance;
      sums.log_variances += std::log(innovation_variance);
      ++sums.num_innovations;
      const double gain = predicted / innovation_variance;
      level += gain * innovation;
      variance = predicted * o.variance / innovation_variance;
    }
  }
  return sums;
}

}  // namespace

ScaleDriftRate EstimateScaleDriftRate(
    const MotionPairs& pairs,
    const std::vector<int>& used,
    const std::vector<PairMetricScale>& pair_scales,
    const std::vector<double>& metric_scales) {
  ScaleDriftRate result;
  if (pair_scales.size() != pairs.size()) return result;
  const std::vector<std::vector<Observation>> series =
      SegmentSeries(pairs, used, &pair_scales, &metric_scales);
  std::vector<double> variances;
  double duration_s = 0.0;
  for (const std::vector<Observation>& observations : series) {
    if (observations.size() < 3) continue;
    ++result.num_segments;
    result.num_pairs += static_cast<int>(observations.size());
    duration_s += observations.back().time_s;
    for (const Observation& o : observations) variances.push_back(o.variance);
  }
  if (result.num_pairs < ScaleDriftRate::kMinPairs || !(duration_s > 0.0)) {
    return result;
  }
  std::nth_element(variances.begin(),
                   variances.begin() + variances.size() / 2,
                   variances.end());
  // Rates on a log grid around the one at which the walk's variance over the
  // drive equals one pair's: 1e-5 to 1e7 times it, and 0.
  const double unit = variances[variances.size() / 2] / duration_s;
  const auto likelihood = [&](double rate) {
    return Filter(series, rate).ProfileLogLikelihood();
  };
  const double at_zero = likelihood(0.0);
  double best_log = 0.0, best = at_zero;
  bool best_positive = false;
  constexpr double kStep = 0.25;  // decades
  for (double decade = -5.0; decade <= 7.0 + 1e-9; decade += kStep) {
    const double value = likelihood(unit * std::pow(10.0, decade));
    if (value > best) {
      best = value;
      best_log = decade;
      best_positive = true;
    }
  }
  if (best_positive) {
    // Golden section on the decade within one grid step either side.
    double low = best_log - kStep, high = best_log + kStep;
    const double ratio = 0.5 * (std::sqrt(5.0) - 1.0);
    double a = high - ratio * (high - low), b = low + ratio * (high - low);
    double fa = likelihood(unit * std::pow(10.0, a));
    double fb = likelihood(unit * std::pow(10.0, b));
    for (int iteration = 0; iteration < 30; ++iteration) {
      if (fa > fb) {
        high = b;
        b = a;
        fb = fa;
        a = high - ratio * (high - low);
        fa = likelihood(unit * std::pow(10.0, a));
      } else {
        low = a;
        a = b;
        fa = fb;
        b = low + ratio * (high - low);
        fb = likelihood(unit * std::pow(10.0, b));
      }
    }
    const double decade = fa > fb ? a : b;
    if (std::max(fa, fb) > best) {
      best = std::max(fa, fb);
      best_log = decade;
    }
  }
  const double rate = best_positive ? unit * std::pow(10.0, best_log) : 0.0;
  const FilterSums sums = Filter(series, rate);
  if (sums.num_innovations == 0) return result;
  result.estimated = true;
  result.scatter_factor = sums.weighted_squares / sums.num_innovations;
  result.rate_per_s = result.scatter_factor * rate;
  result.likelihood_ratio = best_positive ? 2.0 * (best - at_zero) : 0.0;
  return result;
}

Eigen::MatrixXd ScaleDriftCovariance(const MotionPairs& pairs,
                                     const std::vector<int>& used,
                                     const Eigen::MatrixXd& information,
                                     const Eigen::MatrixXd& sensitivity,
                                     double rate_per_s) {
  const Eigen::Index n = information.rows();
  if (n == 0 || sensitivity.rows() != n ||
      sensitivity.cols() != static_cast<Eigen::Index>(used.size()) ||
      !(rate_per_s >= 0.0) || !std::isfinite(rate_per_s)) {
    return Eigen::MatrixXd();
  }
  const std::optional<Eigen::MatrixXd> inverse =
      internal::InvertInformation(information);
  if (!inverse) return Eigen::MatrixXd();
  // B K B^T for K_ij = q min(t_i, t_j) within a segment: with the pairs in
  // time order, min(t_i, t_j) = sum over m <= min(i, j) of (t_m - t_m-1), so
  // B K B^T = q sum_m (t_m - t_m-1) S_m S_m^T with S_m the sum of B's
  // columns from m on: linear in the number of pairs.
  // Each segment's columns are centred: the walk is taken about its mean
  // over the segment's pairs, not about its value at the first pair. That
  // leaves the extrinsic's rows as they are (a constant wander moves only
  // the segment's scale) and keeps in the scale's rows only what the wander
  // does to the scale of the segment as a whole.
  Eigen::MatrixXd spread = Eigen::MatrixXd::Zero(n, n);
  for (const std::vector<Observation>& observations :
       SegmentSeries(pairs, used, nullptr, nullptr)) {
    Eigen::VectorXd mean = Eigen::VectorXd::Zero(n);
    for (const Observation& o : observations) {
      mean += sensitivity.col(o.index);
    }
    mean /= static_cast<double>(observations.size());
    Eigen::VectorXd tail = Eigen::VectorXd::Zero(n);
    for (size_t m = observations.size(); m-- > 1;) {
      tail += sensitivity.col(observations[m].index) - mean;
      const double step = observations[m].time_s - observations[m - 1].time_s;
      spread += step * tail * tail.transpose();
    }
  }
  return rate_per_s * (*inverse) * spread * (*inverse);
}

ScaleDriftTerm AddScaleDriftCovariance(
    const MotionPairs& pairs,
    const std::vector<int>& used,
    const Rigid3d& odom_from_cam,
    const std::vector<double>& metric_scales,
    const CalibrationOptions& options,
    const std::vector<int>& information_segments,
    double z_prior_information,
    Eigen::MatrixXd* information) {
  ScaleDriftTerm term;
  const Eigen::Index n = information->rows();
  const Eigen::Index num_scales =
      static_cast<Eigen::Index>(information_segments.size());
  if (n < 5 || (n != 5 + num_scales && n != 6 + num_scales)) return term;
  term.rate = EstimateScaleDriftRate(
      pairs,
      used,
      PerPairMetricScales(pairs, odom_from_cam, metric_scales, options.noise),
      metric_scales);
  if (!term.rate.estimated || !(term.rate.rate_per_s > 0.0) ||
      !(term.rate.likelihood_ratio >
        ScaleDriftRate::kSignificantLikelihoodRatio)) {
    return term;
  }
  const bool with_z = n == 6 + num_scales;
  HandEyeSensitivity sensitivity = HandEyeScaleSensitivity(
      pairs,
      used,
      odom_from_cam,
      metric_scales,
      options,
      with_z ? TranslationZ::kEstimate : TranslationZ::kHold);
  if (sensitivity.information.rows() != n ||
      sensitivity.information_segments != information_segments) {
    return term;
  }
  if (with_z) sensitivity.information(n - 1, n - 1) += z_prior_information;
  const Eigen::MatrixXd drift =
      ScaleDriftCovariance(pairs,
                           used,
                           sensitivity.information,
                           sensitivity.scale_sensitivity,
                           term.rate.rate_per_s);
  const std::optional<Eigen::MatrixXd> covariance =
      internal::InvertInformation(*information);
  if (drift.size() == 0 || !drift.allFinite() || !covariance) return term;
  const Eigen::MatrixXd widened = *covariance + drift;
  const std::optional<Eigen::MatrixXd> widened_information =
      internal::InvertInformation(widened);
  if (!widened_information) return term;
  const Eigen::Matrix<double, 5, 1> unit =
      (Eigen::Matrix<double, 5, 1>() << kRadToDeg,
       kRadToDeg,
       kRadToDeg,
       1.0,
       1.0)
          .finished();
  for (int k = 0; k < 5; ++k) {
    term.stddev_before(k) = std::sqrt((*covariance)(k, k)) * unit(k);
    term.stddev_after(k) = std::sqrt(widened(k, k)) * unit(k);
    term.named |= drift(k, k) > (*covariance)(k, k);
  }
  *information = *widened_information;
  term.applied = true;
  return term;
}

std::string ScaleDriftWarning(const ScaleDriftTerm& term) {
  // The walk's spread over a minute, in percent.
  const double per_minute = 100.0 * std::sqrt(term.rate.rate_per_s * 60.0);
  std::string widened;
  const char* names[5] = {"rx", "ry", "rz", "x", "y"};
  for (int k = 0; k < 5; ++k) {
    if (!(term.stddev_after(k) > std::sqrt(2.0) * term.stddev_before(k))) {
      continue;
    }
    const bool angle = k < 3;
    const double factor = angle ? 1.0 : 1000.0;  // m -> mm
    widened += std::string(widened.empty() ? "" : ", ") + names[k] + " " +
               FormatRounded(term.stddev_before(k) * factor, 2) + " -> " +
               FormatRounded(term.stddev_after(k) * factor, 2) +
               (angle ? " deg" : " mm");
  }
  return "the reconstruction's scale wanders along the drive by about " +
         FormatRounded(per_minute, 2) +
         " % per minute (a random walk fitted to the camera's step lengths "
         "against the odometry), which one scale per segment cannot follow: "
         "turns mapped at different scales move the lever arm, so the "
         "standard deviations include it (" +
         widened + ")";
}

}  // namespace odomcal
