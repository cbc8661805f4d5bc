// The clock offset and odometry intrinsics in the result JSON, the printed
// summary and the warnings (adapters/systematics_estimation.h).
#pragma once

#include "odomcal/adapters/systematics_estimation.h"
#include "odomcal/solver/calibration_result.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>

namespace odomcal {

// Top-level camera_time_offset_s and odometry_intrinsics, their standard
// deviations in out["stddev"] (when it is an object) and
// diagnostics.time_offset.
void AddSystematicsJson(const SystematicsEstimate& estimate,
                        nlohmann::json* out);

// "  clock offset: odometry_time = camera_time + 0.3001 s  +- 0.6 ms (3
// sigma), estimated\n  odometry intrinsics: yaw_scale ..." lines.
std::string SystematicsSummary(const SystematicsEstimate& estimate);

// A warning when the clock offset was to be estimated and could not be
// (with why); held intrinsics are listed in the JSON and the summary.
void AddSystematicsWarnings(const SystematicsEstimate& estimate,
                            CalibrationResult* result);

// Unequal wheels add a forward distance of yaw_per_metre b^2 / (4 yaw_scale)
// per radian of turn, b the wheel track (docs/systematics.md), which moves
// the extrinsic's y by about that much unless --wheel_track_m gives b
// (applies when the odometry's heading comes from the wheel encoders): a
// warning when a successful calibration estimated yaw_per_metre nonzero
// (beyond 3 sigma), b was not given, and that shift exceeds y's stated 3
// sigma for a track narrower than kWidestWheelTrackM. Measured on
// the rendered 1 000-image drive (wheels +0.3 / -0.2 %, 0.4 m track): y 0.62
// mm off against a 3 sigma of 0.27 mm, 0.12 mm with --wheel_track_m 0.4.
inline constexpr double kWidestWheelTrackM = 1.5;
std::optional<std::string> WheelTrackWarning(
    const SystematicsEstimate& estimate, const CalibrationResult& result);

}  // namespace odomcal
