// The joint adjustment (plugin/colmap/joint_adjustment_stage.h) in the
// writers: its JSON object, its summary lines and its report section.
#pragma once

#include "odomcal/plugin/colmap/colmap_calibration.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace odomcal {

// `joint_adjustment` of the result JSON; null when --joint_adjustment off.
nlohmann::json JointAdjustmentToJson(const ColmapCalibrationRun& run);

// `camera_intrinsics` of an adjustment: per camera its projection model,
// whether its intrinsics were refined (`refine_intrinsics` and not held),
// and its parameters before and after (`before` and `after` of one length).
nlohmann::json JointCameraIntrinsicsToJson(
    const std::vector<JointCamera>& before,
    bool refine_intrinsics,
    const std::vector<JointCamera>& after);

// `diagnostics.two_step`: the two-step extrinsic and its standard deviations
// when the joint adjustment replaced it; null otherwise.
nlohmann::json TwoStepToJson(const ColmapCalibrationRun& run);

// The summary's lines about the adjustment ("" when off), each starting
// with two spaces and ending with a newline.
std::string JointAdjustmentSummary(const ColmapCalibrationRun& run);

// The report's "Joint adjustment" section ("" when it did not run).
std::string JointAdjustmentHtml(const ColmapCalibrationRun& run);

}  // namespace odomcal
