// Calibration flags shared by the commands that calibrate (calibrate, colmap,
// run, demo), as tables (option_table.h): the flags, their defaults and
// checks, and the result JSON's echo all come from these rows. Flag names are
// public interface: keep them stable (docs/cli.md). No CLI11 here: the
// library echoes the options from these tables; the command line registers
// them (command_flags.h).
#pragma once

#include "odomcal/adapters/association.h"
#include "odomcal/adapters/robot_description.h"
#include "odomcal/adapters/systematics_estimation.h"
#include "odomcal/plugin/options/option_table.h"
#include "odomcal/solver/calibration_options.h"

#include <nlohmann/json.hpp>

namespace odomcal {

// --camera_time_offset_s, --max_odometry_gap_s, --keyframe_min_* (echoed in
// `inputs`).
const OptionTable<AssociationOptions>& AssociationFlags();
// The estimator, outliers, noise model and refusal thresholds (echoed in
// `options`, the noise model in `options.noise`).
const OptionTable<CalibrationOptions>& CalibrationOptionFlags();

// --estimate_time_offset, --time_offset_search_s,
// --estimate_odometry_intrinsics, --wheel_track_m (echoed in `options`).
const OptionTable<SystematicsEstimationOptions>& SystematicsFlags();

// --base_frame, --camera_frame, --camera_body_frame: the frames of the robot
// outputs (echoed in `options`).
const OptionTable<RobotFrameNames>& RobotFrameFlags();

// The echo of the association, calibration, systematics and robot frame
// flags, for ReportContext::flag_echo (the default of CalibrationToJson):
// {"inputs": {...}, "options": {...}}.
nlohmann::json CalibrationFlagsEcho(
    const AssociationOptions& association,
    const CalibrationOptions& calibration,
    const SystematicsEstimationOptions& systematics = {},
    const RobotFrameNames& robot_frames = {});

}  // namespace odomcal
