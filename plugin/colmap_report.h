// Reports of a COLMAP-project calibration: the result JSON (the schema of
// calibration_report.h plus a "colmap" section) and a self-contained HTML
// report with inline SVG plots.
#pragma once

#include "odomcal/plugin/colmap_calibration.h"

#include <nlohmann/json.hpp>

#include <string>

namespace odomcal {

nlohmann::json ColmapCalibrationToJson(const ColmapCalibrationRun& run);

// report.html: the estimate with 3-sigma bounds, warnings, and plots: top
// view of the odometry and the calibrated camera trajectory, per-pair
// residuals, yaw excitation, and the COLMAP-vs-odometry consistency with
// rejected stretches marked.
std::string ColmapReportHtml(const ColmapCalibrationRun& run);

}  // namespace odomcal
