#include "odomcal/solver/planarity_check.h"

#include "odomcal/solver/angles.h"
#include "odomcal/solver/chi_square.h"
#include "odomcal/solver/f_distribution.h"
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

// A used pair's out-of-plane rotation residual (radians), its information
// and the odometry's yaw (radians).
struct GroundTerm {
  Eigen::Vector2d tilt = Eigen::Vector2d::Zero();
  Eigen::Matrix2d information = Eigen::Matrix2d::Zero();
  double yaw = 0.0;
};

// A window needs turns to show the ground's tilt: below this sum of
// squared yaws (radians^2; a single 5 deg turn) it is left out.
constexpr double kMinWindowYawSquared = 0.0076;

// Fits tilt = yaw * c per window (c = (-pitch, roll) of the ground) and
// tests the explained tilt variance against the rest (F test, 99.9 %).
void TestGroundTilt(const std::vector<GroundTerm>& terms,
                    const std::map<int, std::vector<size_t>>& by_segment,
                    PlanarityCheck* check) {
  double total = 0.0;  // chi-square of the tilt components
  for (const GroundTerm& term : terms) {
    total += term.tilt.dot(term.information * term.tilt);
  }
  double explained = 0.0;
  std::vector<Eigen::Vector2d> fits;
  std::vector<Eigen::Matrix2d> fit_covariances;  // at unit noise level
  for (const auto& [segment, members] : by_segment) {
    const size_t count =
        std::max<size_t>(1, members.size() / kGroundWindowPairs);
    for (size_t w = 0; w < count; ++w) {
      Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
      Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
      double yaw_squared = 0.0;
      for (size_t m = w * members.size() / count;
           m < (w + 1) * members.size() / count;
           ++m) {
        const GroundTerm& term = terms[members[m]];
        normal += term.yaw * term.yaw * term.information;
        rhs += term.yaw * term.information * term.tilt;
        yaw_squared += term.yaw * term.yaw;
      }
      if (yaw_squared < kMinWindowYawSquared) continue;
      const Eigen::Matrix2d covariance = normal.inverse();
      if (!covariance.allFinite()) continue;
      fits.push_back(covariance * rhs);
      fit_covariances.push_back(covariance);
      explained += rhs.dot(covariance * rhs);
    }
  }
  const int windows = static_cast<int>(fits.size());
  // Roll and pitch of the estimate were fitted to the same components.
  const double rest_dof =
      2.0 * static_cast<double>(terms.size()) - 2.0 * windows - 2.0;
  check->ground_windows = windows;
  if (windows < 2 || rest_dof < 10.0) return;
  const double rest = total - explained;
  if (!(rest > 0.0)) return;
  check->ground_tested = true;
  const double rest_variance = rest / rest_dof;
  check->ground_f_statistic = (explained / (2.0 * windows)) / rest_variance;
  check->ground_f_threshold =
      FDistributionCriticalValue(1e-3, 2.0 * windows, rest_dof);
  check->ground_tilt_seen =
      check->ground_f_statistic > check->ground_f_threshold;
  // The fitted tilt's spread, its fitting noise at the residual level
  // subtracted.
  Eigen::Vector2d spread = Eigen::Vector2d::Zero();
  for (int w = 0; w < windows; ++w) {
    spread +=
        fits[w].cwiseAbs2() - rest_variance * fit_covariances[w].diagonal();
  }
  spread = (spread / windows).cwiseMax(0.0).cwiseSqrt();
  check->ground_pitch_rms_deg = spread(0) * kRadToDeg;
  check->ground_roll_rms_deg = spread(1) * kRadToDeg;
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
  std::vector<GroundTerm> ground(used.size());
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
    ground[k].tilt = r.head<2>();
    ground[k].information = sigma.topLeftCorner<2, 2>().inverse();
    ground[k].yaw = LogRotation(pair.odom_i_from_odom_j.rotation).z();
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

  // The ground's tilt per window (in time order within each segment).
  std::map<int, std::vector<size_t>> by_segment;  // positions in `used`
  for (size_t k = 0; k < used.size(); ++k) {
    by_segment[pairs[used[k]].segment].push_back(k);
  }
  for (auto& [segment, members] : by_segment) {
    std::stable_sort(members.begin(), members.end(), [&](size_t a, size_t b) {
      return pairs[used[a]].stamp_i_ns < pairs[used[b]].stamp_i_ns;
    });
  }
  TestGroundTilt(ground, by_segment, &check);

  // Worst stretch: the window of consecutive used pairs of one segment (in
  // time order) with the largest chi-square sum; a window never spans two
  // segments, whose times may be far apart or overlap.
  const size_t full_window = std::max<size_t>(3, used.size() / 10);
  double best_sum = -1.0;
  std::vector<size_t> worst;  // positions in `used` of the worst window
  for (const auto& [segment, members] : by_segment) {
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

Eigen::Matrix4d GroundTiltCovariance(const PlanarityCheck& check,
                                     double height_m,
                                     double height_m2) {
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Zero();  // rx, ry, tx, ty
  if (!check.ground_tilt_seen) return covariance;
  const double roll2 = std::pow(check.ground_roll_rms_deg * kDegToRad, 2);
  const double pitch2 = std::pow(check.ground_pitch_rms_deg * kDegToRad, 2);
  // A tilt G by (roll, pitch) moves the extrinsic to G * odom_from_cam:
  // rotation by the tilt, translation by tilt x p (tx = pitch h,
  // ty = -roll h): the error's covariance, with the height's moments.
  covariance(0, 0) = roll2;
  covariance(1, 1) = pitch2;
  covariance(2, 2) = height_m2 * pitch2;
  covariance(3, 3) = height_m2 * roll2;
  covariance(0, 3) = covariance(3, 0) = -height_m * roll2;
  covariance(1, 2) = covariance(2, 1) = height_m * pitch2;
  return covariance;
}

std::string GroundTiltWarning(const PlanarityCheck& check,
                              const Eigen::Vector2d& stddev_before_deg,
                              const Eigen::Vector2d& stddev_after_deg) {
  return "the ground is not level: the camera's rotation axes show its roll "
         "varying by " +
         Short(check.ground_roll_rms_deg) + " deg RMS and its pitch by " +
         Short(check.ground_pitch_rms_deg) +
         " deg RMS along the drive (F = " + Short(check.ground_f_statistic) +
         ", threshold " + Short(check.ground_f_threshold) +
         "), which planar odometry cannot see; a mean tilt of that size "
         "moves roll and pitch by as much and x, y by the camera's height "
         "times it: their standard deviations include it (roll " +
         Short(stddev_before_deg(0)) + " -> " + Short(stddev_after_deg(0)) +
         " deg, pitch " + Short(stddev_before_deg(1)) + " -> " +
         Short(stddev_after_deg(1)) +
         " deg). Give the camera's height (--fixed_translation_z_m) for x, "
         "y; SE(3) odometry (roll, pitch, z) avoids this";
}

}  // namespace odomcal
