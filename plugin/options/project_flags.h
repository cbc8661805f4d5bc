// Flags shared by the commands that calibrate a COLMAP project
// (`odomcal colmap`, `odomcal run`), as tables (option_table.h) bound to
// ColmapCalibrationInputs, and the echo of a project calibration's options.
// No CLI11 here: the command line registers the flags (command_flags.h).
#pragma once

#include "odomcal/plugin/colmap/colmap_calibration.h"
#include "odomcal/plugin/options/cli_flags.h"
#include "odomcal/plugin/options/option_table.h"

#include <nlohmann/json.hpp>

namespace odomcal {

// `odomcal colmap`'s --model_path and --database_path (echoed in `inputs`
// for `odomcal run` too, which sets them to its workspace's).
const OptionTable<ColmapCalibrationInputs>& ColmapModelFlags();
// --odometry, --image_timestamps, --file_name_time_unit (echoed in
// `inputs`).
const OptionTable<ColmapCalibrationInputs>& ProjectInputFlags();
// The stretch check's --min_inconsistent_run_pairs (echoed in `options`).
const OptionTable<StretchOptions>& StretchFlags();

// The floor plane's --floor_plane, --odometry_height_m and tuning (echoed
// in `options`).
const OptionTable<FloorPlaneOptions>& FloorPlaneFlags();

// --joint_adjustment and its tuning (echoed in `options`).
const OptionTable<JointAdjustmentSettings>& JointAdjustmentFlags();

// The echo of `odomcal colmap`'s flags as `inputs` holds them, for
// ProjectReportContext (its default): the calibration flags, --model_path
// and --database_path (null when not given), the project inputs and the
// stretch check's flags.
nlohmann::json ProjectFlagsEcho(const ColmapCalibrationInputs& inputs);

}  // namespace odomcal
