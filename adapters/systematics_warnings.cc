#include "odomcal/adapters/systematics_warnings.h"

#include "odomcal/adapters/timestamp.h"
#include "odomcal/solver/format_number.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace odomcal {

void AddSystematicsWarnings(const SystematicsEstimate& estimate,
                            CalibrationResult* result) {
  if (!estimate.time_offset_estimated &&
      estimate.time_offset_reason != "--estimate_time_offset off") {
    result->warnings.push_back(
        "camera_time_offset_s not estimated (" + estimate.time_offset_reason +
        "): kept at " +
        FormatNumber(NsToSeconds(estimate.camera_time_offset_ns)) + " s");
  }
  // Held intrinsics are named in odometry_intrinsics.held and the summary
  // only: a short drive rarely determines all three, which is no fault.
  if (const auto warning = WheelTrackWarning(estimate, *result)) {
    result->warnings.push_back(*warning);
  }
}

std::optional<std::string> WheelTrackWarning(
    const SystematicsEstimate& estimate, const CalibrationResult& result) {
  const OdometryIntrinsics& intrinsics = estimate.intrinsics;
  const double yaw_per_metre = std::abs(intrinsics.yaw_per_metre_rad);
  if (!result.IsSuccess() || !estimate.intrinsics_estimated[1] ||
      intrinsics.wheel_track_m > 0.0 ||
      !(yaw_per_metre > 3.0 * estimate.intrinsics_stddev[1]) ||
      !(intrinsics.yaw_scale > 0.0)) {
    return std::nullopt;
  }
  // y is off by about yaw_per_metre b^2 / (4 yaw_scale) for a track b.
  const auto y_bias_m = [&](double track_m) {
    return yaw_per_metre * track_m * track_m / (4.0 * intrinsics.yaw_scale);
  };
  const double y_three_sigma_m = 3.0 * result.stddev_translation_xy_m.y();
  if (!(y_three_sigma_m > 0.0)) return std::nullopt;
  const double track_beyond_m =
      std::sqrt(4.0 * intrinsics.yaw_scale * y_three_sigma_m / yaw_per_metre);
  if (!(track_beyond_m < kWidestWheelTrackM)) return std::nullopt;
  return "unequal wheels (yaw_per_metre " +
         FormatRounded(intrinsics.yaw_per_metre_rad, 3) +
         " rad/m) and no --wheel_track_m: if the odometry's heading comes "
         "from the wheel encoders, translation y would be off by about "
         "yaw_per_metre * b^2 / 4 for a wheel track b (" +
         FormatRounded(1e3 * y_bias_m(0.4), 2) +
         " mm for 0.4 m), more than its stated 3 sigma (" +
         FormatRounded(1e3 * y_three_sigma_m, 2) + " mm) for a track over " +
         FormatRounded(track_beyond_m, 2) + " m; give --wheel_track_m";
}

}  // namespace odomcal
