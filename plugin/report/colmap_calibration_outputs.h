// The files of a project calibration (`odomcal colmap`, `odomcal run`):
// the result JSON and YAML, the model in metres, the camera trajectory in
// the odometry frame and the HTML report.
#pragma once

#include "odomcal/adapters/robot_description.h"
#include "odomcal/plugin/colmap/colmap_calibration.h"
#include "odomcal/plugin/report/calibration_report.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace odomcal {

// The entries WriteColmapCalibrationOutputs writes in its folder (for
// ClaimOutputFolder, output_folder.h): also a rig's cameras/.
std::vector<std::string> ColmapCalibrationOutputEntries();

// Writes into `output_dir` (which must exist and be claimed for the entries
// above): calibration.json/.yaml, the robot outputs (calibration.urdf,
// calibration_tf_ros2.sh, ..., robot_outputs.h) when the extrinsic is
// calibrated, sparse_metric/<sub-model>/ (COLMAP binary), camera_in_odom.tum
// and report.html. Every file is written atomically.
// sparse_metric/ and camera_in_odom.tum are written only when they hold a
// model or a pose (without an extrinsic there is nothing to put in metres:
// an empty folder or a header-only file would read as a result); an earlier
// run's are removed. `context` (ProjectReportContext, colmap_report.h) is
// echoed in the JSON and the report. Returns what it wrote:
// "calibration.json", "calibration.yaml", ["calibration.urdf", ...,
// "sparse_metric/", "camera_in_odom.tum",] "report.html".
std::vector<std::string> WriteColmapCalibrationOutputs(
    const ColmapCalibrationRun& run,
    const ReportContext& context,
    const std::string& output_dir);

// A rig's top-level files in place of its reference camera's own: the
// result JSON (with the rig's cameras), the robot outputs (every camera's
// transforms) and report.html with the rig's section (RigReportHtml,
// rig_report_html.h). The rig writes cameras/ itself.
struct RigOverrides {  // NOLINT(bugprone-exception-escape)
  nlohmann::json result;
  std::optional<RobotDescription> robot;
  std::string report_section;
};
// As above, with `rig`'s JSON, robot outputs and report; a single camera's call
// removes an earlier rig run's cameras/.
std::vector<std::string> WriteColmapCalibrationOutputs(
    const ColmapCalibrationRun& run,
    const ReportContext& context,
    const std::string& output_dir,
    const RigOverrides* rig);

}  // namespace odomcal
