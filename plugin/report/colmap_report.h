// Reports of a COLMAP-project calibration: the result JSON (the schema of
// calibration_report.h plus a "colmap" section) and a self-contained HTML
// report with inline SVG plots.
#pragma once

#include "odomcal/plugin/colmap/colmap_calibration.h"
#include "odomcal/plugin/report/calibration_report.h"

#include <nlohmann/json.hpp>

#include <string>

namespace odomcal {

// The report's account of a project calibration: `inputs`' paths, time
// units and options, the sub-models and association of `run`, `command`
// ("odomcal colmap") and the echo of its flags, ProjectFlagsEcho(inputs)
// (project_flags.h) unless another is given (`odomcal run` adds its own
// flags', RunFlagsEcho).
ReportContext ProjectReportContext(const ColmapCalibrationInputs& inputs,
                                   const ColmapCalibrationRun& run,
                                   const std::string& command);
ReportContext ProjectReportContext(const ColmapCalibrationInputs& inputs,
                                   const ColmapCalibrationRun& run,
                                   const std::string& command,
                                   nlohmann::json flag_echo);

nlohmann::json ColmapCalibrationToJson(const ColmapCalibrationRun& run,
                                       const ReportContext& context);

// report.html: the estimate with 3-sigma bounds, warnings, and plots: top
// view of the odometry and the calibrated camera trajectory, per-pair
// residuals, yaw excitation, and the COLMAP-vs-odometry consistency with
// rejected stretches marked.
std::string ColmapReportHtml(const ColmapCalibrationRun& run,
                             const ReportContext& context);

// A rig's report.html (its reference camera's run and context): `rig`'s
// section (RigReportHtml, rig_report_html.h) after the warnings, and "Use
// it" with the rig's robot outputs (every camera's transforms). Null: as
// above.
struct RigOverrides;  // colmap_calibration_outputs.h
std::string ColmapReportHtml(const ColmapCalibrationRun& run,
                             const ReportContext& context,
                             const RigOverrides* rig);

}  // namespace odomcal
