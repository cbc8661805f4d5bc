// The outputs of a COLMAP project with several cameras (`odomcal colmap` on
// a rig, colmap_rig_calibration.h). In the output folder:
//   - the reference camera's files (calibration.json/.yaml, sparse_metric/,
//     camera_in_odom.tum, report.html), the JSON with the rig's `cameras`,
//     `camera_pairs` and `shared_scales` (docs/result_schema.md), robot
//     outputs with one transform chain per calibrated camera, and
//     report.html with the rig's section (rig_report_html.h);
//   - cameras/<name>/ per calibrated camera: that camera's own files, as a
//     single-camera project's.
#pragma once

#include "odomcal/plugin/cli/rig_calibration.h"
#include "odomcal/plugin/colmap/colmap_rig_calibration.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace odomcal {

// The rig as the rig report sees it: per camera its result and report
// context (`flag_echo` in each), its pairs, and the shared-scale warnings.
RigCalibrationRun RigCalibrationOf(const ColmapRigRun& rig,
                                   const std::string& command,
                                   const nlohmann::json& flag_echo);

// The rig's calibration.json: the reference camera's project result with
// the rig's keys.
nlohmann::json ColmapRigToJson(const ColmapRigRun& rig,
                               const RigCalibrationRun& as_rig);

// Writes the files above into `output_dir` (claimed for
// ColmapCalibrationOutputEntries()). `as_rig` is RigCalibrationOf(rig) or
// alike. Without `write_camera_folders`, cameras/<name>/ are the cameras'
// own workspaces (`run --rig`), written already, and left as they are.
// Returns what it wrote, "cameras/front/" for a camera's folder.
std::vector<std::string> WriteColmapRigOutputs(const ColmapRigRun& rig,
                                               const RigCalibrationRun& as_rig,
                                               const std::string& output_dir,
                                               bool write_camera_folders);

}  // namespace odomcal
