// Grid search: step = a quarter of the median odometry period (at most 10 ms),
// then a 0.5 ms grid around the best step. Correlation is Pearson's over the
// camera intervals whose shifted interval lies inside the odometry (at least
// half of them).
#include "odomcal/adapters/time_offset_search.h"

#include "odomcal/adapters/association.h"
#include "odomcal/adapters/timestamp.h"
#include "odomcal/solver/format_number.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

namespace odomcal {
namespace {

struct Interval {
  int64_t from_ns, to_ns;
  double camera_angle_rad;
};

// Correlation of camera and odometry rotation angles at `offset_ns`; NaN
// when fewer than half the intervals (or < 10) have odometry.
double Correlation(const std::vector<Interval>& intervals,
                   const Trajectory& odometry,
                   double max_gap_s,
                   int64_t offset_ns,
                   int* num_used) {
  double n = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  for (const Interval& interval : intervals) {
    const std::optional<Rigid3d> a = InterpolateOdometry(
        odometry, interval.from_ns + offset_ns, max_gap_s, nullptr);
    if (!a) continue;
    const std::optional<Rigid3d> b = InterpolateOdometry(
        odometry, interval.to_ns + offset_ns, max_gap_s, nullptr);
    if (!b) continue;
    const double x = interval.camera_angle_rad;
    const double y = RotationAngle((Inverse(*a) * *b).rotation);
    n += 1;
    sx += x;
    sy += y;
    sxx += x * x;
    syy += y * y;
    sxy += x * y;
  }
  *num_used = static_cast<int>(n);
  if (n < 10 || 2 * n < intervals.size()) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  const double vx = sxx - sx * sx / n, vy = syy - sy * sy / n;
  if (!(vx > 0.0) || !(vy > 0.0)) return 0.0;
  return (sxy - sx * sy / n) / std::sqrt(vx * vy);
}

}  // namespace

TimeOffsetSearch SearchTimeOffset(const std::vector<Trajectory>& cameras,
                                  const Trajectory& odometry,
                                  const TimeOffsetSearchOptions& options) {
  if (!(options.range_s > 0.0) || !std::isfinite(options.range_s)) {
    throw std::invalid_argument(
        "time_offset_search_s must be finite and > 0, got " +
        FormatNumber(options.range_s));
  }
  TimeOffsetSearch search;
  search.peak_ns = options.center_ns;
  std::vector<Interval> intervals;
  for (const Trajectory& camera : cameras) {
    for (size_t k = 1; k < camera.poses.size(); ++k) {
      intervals.push_back(
          {camera.poses[k - 1].stamp_ns,
           camera.poses[k].stamp_ns,
           RotationAngle((Inverse(camera.poses[k - 1].world_from_sensor) *
                          camera.poses[k].world_from_sensor)
                             .rotation)});
    }
  }
  std::vector<double> periods;
  for (size_t k = 1; k < odometry.poses.size(); ++k) {
    periods.push_back(ElapsedSeconds(odometry.poses[k - 1].stamp_ns,
                                     odometry.poses[k].stamp_ns));
  }
  if (intervals.size() < 10 || periods.empty()) {
    search.reason = "too few camera poses or odometry samples";
    return search;
  }
  std::nth_element(
      periods.begin(), periods.begin() + periods.size() / 2, periods.end());
  const double median_period_s = periods[periods.size() / 2];
  if (median_period_s > options.max_odometry_gap_s) {
    search.reason = "odometry too sparse (median period " +
                    FormatRounded(median_period_s) +
                    " s > max_odometry_gap_s " +
                    FormatNumber(options.max_odometry_gap_s) + " s)";
    return search;
  }
  const double step_s = std::min(0.01, median_period_s / 4.0);
  search.step_s = step_s;
  const int64_t step_ns = static_cast<int64_t>(std::llround(step_s * 1e9));
  const int num_steps = static_cast<int>(std::ceil(options.range_s / step_s));
  std::vector<double> correlation(2 * num_steps + 1);
  int best = -1;
  for (int k = -num_steps; k <= num_steps; ++k) {
    int used = 0;
    const double c = Correlation(intervals,
                                 odometry,
                                 options.max_odometry_gap_s,
                                 options.center_ns + k * step_ns,
                                 &used);
    correlation[k + num_steps] = c;
    if (std::isfinite(c) && (best < 0 || c > correlation[best])) {
      best = k + num_steps;
    }
  }
  if (best < 0) {
    search.reason =
        "the camera and the odometry overlap too little over the search range";
    return search;
  }
  // Fine grid around the best step.
  const int64_t coarse_ns = options.center_ns + (best - num_steps) * step_ns;
  int64_t peak_ns = coarse_ns;
  double peak = correlation[best];
  int used_at_peak = 0;
  for (int64_t d = -step_ns; d <= step_ns; d += 500000) {
    int used = 0;
    const double c = Correlation(
        intervals, odometry, options.max_odometry_gap_s, coarse_ns + d, &used);
    if (std::isfinite(c) && c >= peak) {
      peak = c;
      peak_ns = coarse_ns + d;
      used_at_peak = used;
    }
  }
  if (used_at_peak == 0) {
    Correlation(intervals,
                odometry,
                options.max_odometry_gap_s,
                peak_ns,
                &used_at_peak);
  }
  search.peak_ns = peak_ns;
  search.peak_correlation = peak;
  search.num_intervals = used_at_peak;
  // Half width: furthest grid offset whose correlation is within peak_drop.
  double half_width_s = 0.0;
  for (int k = 0; k <= 2 * num_steps; ++k) {
    if (std::isfinite(correlation[k]) &&
        correlation[k] >= peak - options.peak_drop) {
      half_width_s = std::max(half_width_s, std::abs(k - best) * step_s);
    }
  }
  search.peak_half_width_s = half_width_s;
  if (best == 0 || best == 2 * num_steps) {
    search.reason = "the correlation peaks at the edge of the search range (" +
                    FormatNumber(options.range_s) +
                    " s): widen it with --time_offset_search_s";
  } else if (!(peak >= options.min_peak_correlation)) {
    search.reason = "the rotation rates correlate too weakly (peak " +
                    FormatRounded(peak) + " < " +
                    FormatNumber(options.min_peak_correlation) +
                    "): too little or too smooth turning";
  } else if (half_width_s > options.max_peak_half_width_s) {
    search.reason = "the correlation peak is flat (within " +
                    FormatNumber(options.peak_drop) + " of the peak over +-" +
                    FormatRounded(half_width_s) +
                    " s): the motion is too smooth to resolve the offset";
  } else {
    search.resolved = true;
  }
  return search;
}

}  // namespace odomcal
