// The warnings a calibration's result carries about the clock offset and
// the odometry intrinsics (systematics_estimation.h): computed with the
// estimate, so that the project calibration (odomcal::plugin) and the
// command line add the same lines.
#pragma once

#include "odomcal/adapters/systematics_estimation.h"
#include "odomcal/solver/calibration_result.h"

#include <optional>
#include <string>

namespace odomcal {

// A warning when the clock offset was to be estimated and could not be
// (with why). Held intrinsics are listed in the JSON and the summary.
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
