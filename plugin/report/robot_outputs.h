// The calibration as robots load it (adapters/robot_description.h): the
// result JSON's `robot` section, the files beside calibration.json and the
// summary's lines, all from one RobotDescription.
#pragma once

#include "odomcal/adapters/robot_description.h"
#include "odomcal/plugin/report/calibration_report.h"
#include "odomcal/solver/calibration_result.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace odomcal {

// None unless the calibration succeeded with rotation, x and y estimated
// (a robot must not be given a partial or refused extrinsic). The frames
// are context.robot_frames; the wheel corrections come from
// context.systematics when the odometry intrinsics were estimated and
// --wheel_track_m was given.
std::optional<RobotDescription> RobotDescriptionOf(
    const CalibrationResult& result, const ReportContext& context);

// The result JSON's `robot` section (docs/result_schema.md); null without a
// description.
nlohmann::json RobotToJson(const std::optional<RobotDescription>& robot);

struct RobotOutputFile {
  std::string suffix;  // appended to the result's stem
  std::string text;
};

// Every suffix a robot output file may have, for the output guard:
// ".urdf", "_tf_ros2.sh", "_tf_ros1.sh", "_autoware.yaml", "_diff_drive.yaml".
std::vector<std::string> RobotOutputSuffixes();

// The files of `robot` (the diff_drive one only with wheel corrections).
std::vector<RobotOutputFile> RobotOutputFiles(const RobotDescription& robot);

// The path of a robot output beside the result JSON: its path without the
// extension, then `suffix` ("out/calibration.json", "_tf_ros2.sh" ->
// "out/calibration_tf_ros2.sh").
std::string RobotOutputPath(const std::string& result_path,
                            const std::string& suffix);

// The report's "Use it" section: each file's text with a copy button, the
// frames and the held height; without a description, why there is none.
std::string RobotUseItHtml(const std::optional<RobotDescription>& robot);

// The summary's lines: the frames, the URDF origin and the ROS 2 tf command
// per transform, the held height, the wheel corrections.
std::string RobotSummary(const RobotDescription& robot);

}  // namespace odomcal
