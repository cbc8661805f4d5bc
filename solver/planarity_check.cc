#include "odomcal/solver/planarity_check.h"

#include "odomcal/solver/angles.h"
#include "odomcal/solver/chi_square.h"
#include "odomcal/solver/format_number.h"
#include "odomcal/solver/hand_eye_residual.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <vector>

namespace odomcal {
namespace {

// Two or three significant digits without an exponent: 0.41, 6.3, 21, 140.
std::string Short(double value) {
  const double magnitude = std::abs(value);
  return FormatPrintf(magnitude >= 100.0  ? "%.0f"
                      : magnitude >= 10.0 ? "%.1f"
                      : magnitude >= 1.0  ? "%.2f"
                                          : "%.2g",
                      value);
}

// Integrated autocorrelation time of the whitened residuals, in pairs: 1 for
// independent noise; a smooth slope makes neighbouring pairs' residuals
// alike, and their effect on the estimate does not average out as 1/n.
// Lags are summed while the autocorrelation stays positive (Sokal's
// truncation), up to a quarter of the pairs.
double CorrelationLength(const std::vector<Eigen::Vector3d>& whitened) {
  const size_t n = whitened.size();
  double energy = 0.0;
  for (const Eigen::Vector3d& w : whitened) energy += w.squaredNorm();
  if (!(energy > 0.0)) return 1.0;
  double length = 1.0;
  for (size_t lag = 1; lag <= n / 4; ++lag) {
    double sum = 0.0;
    for (size_t k = 0; k + lag < n; ++k) {
      sum += whitened[k].dot(whitened[k + lag]);
    }
    const double correlation = sum / energy;
    if (correlation <= 0.0) break;
    length += 2.0 * correlation;
  }
  return length;
}

}  // namespace

bool IsPlanarMotion(const Rigid3d& odom_i_from_odom_j) {
  if (!(std::abs(odom_i_from_odom_j.translation.z()) <= kPlanarTolerance)) {
    return false;
  }
  // A rotation about z alone, as a planar log's: no logarithm needed (the
  // noise model asks this of every pair in every round).
  const Eigen::Quaterniond& q = odom_i_from_odom_j.rotation;
  if (q.x() == 0.0 && q.y() == 0.0) return true;
  return LogRotation(q).head<2>().norm() <= kPlanarTolerance;
}

bool IsPlanarOdometry(const MotionPairs& pairs) {
  for (const MotionPair& pair : pairs) {
    if (!IsPlanarMotion(pair.odom_i_from_odom_j)) return false;
  }
  return true;
}

PlanarityCheck CheckPlanarity(const MotionPairs& pairs,
                              const std::vector<int>& used,
                              const Rigid3d& odom_from_cam,
                              const std::vector<double>& metric_scales,
                              const NoiseModel& noise) {
  PlanarityCheck check;
  if (used.size() < 2 || !IsPlanarOdometry(pairs)) return check;
  check.checked = true;
  check.tilt_deg.assign(pairs.size(), 0.0);
  check.out_of_plane_m.assign(pairs.size(), 0.0);

  std::vector<double> chi_square(used.size(), 0.0);
  std::vector<Eigen::Vector3d> whitened(used.size());
  double sum_tilt2 = 0.0, sum_height2 = 0.0;
  for (size_t k = 0; k < used.size(); ++k) {
    const int i = used[k];
    const MotionPair& pair = pairs[i];
    const double scale = metric_scales[pair.segment];
    const Vector6d residual = HandEyeResidual(pair, odom_from_cam, scale);
    const Matrix6d covariance =
        HandEyeResidualCovariance(pair, odom_from_cam, scale, noise);
    // Out-of-plane components: rotation x, y and translation z.
    const int index[3] = {0, 1, 5};
    Eigen::Vector3d r;
    Eigen::Matrix3d sigma;
    for (int a = 0; a < 3; ++a) {
      r(a) = residual(index[a]);
      for (int b = 0; b < 3; ++b) sigma(a, b) = covariance(index[a], index[b]);
    }
    // The same tiny load as HandEyeSqrtInformation: finite when singular.
    sigma += 1e-18 * Eigen::Matrix3d::Identity();
    const Eigen::LLT<Eigen::Matrix3d> cholesky(sigma);
    whitened[k] = cholesky.matrixL().solve(r);
    chi_square[k] = whitened[k].squaredNorm();
    check.chi_square += chi_square[k];

    const double tilt_deg = r.head<2>().norm() * kRadToDeg;
    const double height_m = -r(2);
    check.tilt_deg[i] = tilt_deg;
    check.out_of_plane_m[i] = height_m;
    sum_tilt2 += tilt_deg * tilt_deg;
    sum_height2 += height_m * height_m;
    check.tilt_max_deg = std::max(check.tilt_max_deg, tilt_deg);
    check.out_of_plane_max_m =
        std::max(check.out_of_plane_max_m, std::abs(height_m));
  }
  const double n = static_cast<double>(used.size());
  check.tilt_rms_deg = std::sqrt(sum_tilt2 / n);
  check.out_of_plane_rms_m = std::sqrt(sum_height2 / n);
  check.degrees_of_freedom = 3 * static_cast<int>(used.size()) - 2;
  check.chi_square_threshold = ChiSquare999(check.degrees_of_freedom);
  check.reduced_chi_square = check.chi_square / check.degrees_of_freedom;
  check.consistent = check.chi_square <= check.chi_square_threshold;
  check.correlation_length = CorrelationLength(whitened);
  check.named = !check.consistent &&
                (check.correlation_length >= kMinSlopeCorrelation ||
                 check.reduced_chi_square >= kMinNamedReducedChiSquare);
  check.covariance_inflation =
      check.consistent
          ? 1.0
          : std::max(1.0, check.reduced_chi_square * check.correlation_length);

  // Worst stretch: the window of consecutive used pairs of one segment (in
  // time order) with the largest chi-square sum; a window never spans two
  // segments, whose times may be far apart or overlap.
  std::map<int, std::vector<size_t>> by_segment;  // positions in `used`
  for (size_t k = 0; k < used.size(); ++k) {
    by_segment[pairs[used[k]].segment].push_back(k);
  }
  const size_t full_window = std::max<size_t>(3, used.size() / 10);
  double best_sum = -1.0;
  std::vector<size_t> worst;  // positions in `used` of the worst window
  for (auto& [segment, members] : by_segment) {
    std::stable_sort(members.begin(), members.end(), [&](size_t a, size_t b) {
      return pairs[used[a]].stamp_i_ns < pairs[used[b]].stamp_i_ns;
    });
    const size_t window = std::min(members.size(), full_window);
    double window_sum = 0.0;
    for (size_t m = 0; m < members.size(); ++m) {
      window_sum += chi_square[members[m]];
      if (m >= window) window_sum -= chi_square[members[m - window]];
      if (m + 1 >= window && window_sum > best_sum) {
        best_sum = window_sum;
        worst.assign(members.begin() + (m + 1 - window),
                     members.begin() + (m + 1));
      }
    }
  }
  check.worst_first_stamp_ns = pairs[used[worst.front()]].stamp_i_ns;
  check.worst_last_stamp_ns = pairs[used[worst.back()]].stamp_j_ns;
  double worst_tilt2 = 0.0, worst_height2 = 0.0;
  for (const size_t k : worst) {
    worst_tilt2 += std::pow(check.tilt_deg[used[k]], 2);
    worst_height2 += std::pow(check.out_of_plane_m[used[k]], 2);
  }
  const double window = static_cast<double>(worst.size());
  check.worst_tilt_rms_deg = std::sqrt(worst_tilt2 / window);
  check.worst_out_of_plane_rms_m = std::sqrt(worst_height2 / window);
  return check;
}

std::string PlanarityWarning(const PlanarityCheck& check,
                             int64_t first_stamp_ns) {
  auto seconds = [&](int64_t stamp_ns) {
    return 1e-9 * static_cast<double>(stamp_ns - first_stamp_ns);
  };
  return "the motion is not planar: per motion pair the camera tilts " +
         Short(check.tilt_rms_deg) + " deg RMS (max " +
         Short(check.tilt_max_deg) + " deg) and moves " +
         Short(1000.0 * check.out_of_plane_rms_m) + " mm RMS (max " +
         Short(1000.0 * check.out_of_plane_max_m) +
         " mm) out of the odometry plane, " + Short(check.reduced_chi_square) +
         "x the noise model's variance, correlated over " +
         Short(check.correlation_length) + " pairs; worst at " +
         FormatPrintf("%.1f", seconds(check.worst_first_stamp_ns)) + "-" +
         FormatPrintf("%.1f", seconds(check.worst_last_stamp_ns)) +
         " s (tilt " + Short(check.worst_tilt_rms_deg) +
         " deg RMS). Planar odometry cannot see slopes or ramps (or the "
         "camera is noisier than the noise model): standard deviations "
         "inflated " +
         Short(std::sqrt(check.covariance_inflation)) + "x";
}

}  // namespace odomcal
