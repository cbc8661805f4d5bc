// The outputs of a rig calibration (rig_calibration.h): the result JSON is
// the reference camera's (calibration_report.h) with `reference_camera`,
// `cameras` and `camera_pairs` added (docs/result_schema.md), the YAML is
// the reference camera's, and the robot outputs hold one transform chain per
// calibrated camera.
#pragma once

#include "odomcal/adapters/robot_description.h"
#include "odomcal/plugin/cli/rig_calibration.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>

namespace odomcal {

// The frames of camera `name` in the robot outputs: NAME_ before the camera
// frame names of `frames` ("front_camera_optical_frame").
RobotFrameNames RigCameraFrames(const RobotFrameNames& frames,
                                const std::string& name);

// The reference camera's run with the rig's warnings added to its result.
CalibrationRun ReferenceRun(const RigCalibrationRun& rig);

nlohmann::json RigCalibrationToJson(const RigCalibrationRun& rig);

// Adds `robot` (every camera's transforms), `reference_camera`, `cameras`,
// `camera_pairs` and their `inputs` to a result JSON.
void AddRigToJson(const RigCalibrationRun& rig, nlohmann::json* result);

// Every calibrated camera's transforms from the base frame; none when no
// camera was calibrated. Wheel corrections come from the reference camera's
// run.
std::optional<RobotDescription> RigRobotDescription(
    const RigCalibrationRun& rig);

// The reference camera's summary, then one block per camera and one line
// per pair.
std::string RigCalibrationSummary(const RigCalibrationRun& rig);

// Writes <output>.json, <output>.yaml and the robot outputs atomically, as
// WriteCalibrationOutputs does for one camera.
void WriteRigCalibrationOutputs(const RigCalibrationRun& rig,
                                const std::string& json_path,
                                bool overwrite);

// kExitSuccess when at least one camera was calibrated.
int RigExitCode(const RigCalibrationRun& rig);

}  // namespace odomcal
