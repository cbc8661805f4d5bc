// The clock offset and odometry intrinsics in the result JSON, the printed
// summary and the warnings (adapters/systematics_estimation.h).
#pragma once

#include "odomcal/adapters/systematics_estimation.h"
#include "odomcal/solver/calibration_result.h"

#include <nlohmann/json.hpp>

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

}  // namespace odomcal
