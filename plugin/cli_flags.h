// Calibration flags shared by the commands that calibrate (calibrate, colmap,
// run, demo), as tables (option_table.h): the flags, their defaults and
// checks, and the result JSON's echo all come from these rows. Flag names are
// public interface: keep them stable (docs/cli.md).
#pragma once

#include "odomcal/adapters/association.h"
#include "odomcal/plugin/calibrate_command.h"
#include "odomcal/plugin/option_table.h"
#include "odomcal/solver/calibration_options.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

namespace odomcal {

// How the input files are read: --odometry_format, --camera_time_unit,
// --odometry_time_unit. No echo functions: the report echoes in `inputs` the
// units and format it is given in ReportContext (for `odomcal colmap`
// without --image_timestamps the camera times come "from image file names").
const OptionTable<CalibrateInputs>& InputFormatFlags();
// --camera_time_offset_s, --max_odometry_gap_s, --keyframe_min_* (echoed in
// `inputs`).
const OptionTable<AssociationOptions>& AssociationFlags();
// The estimator, outliers, noise model and refusal thresholds (echoed in
// `options`, the noise model in `options.noise`).
const OptionTable<CalibrationOptions>& CalibrationOptionFlags();

// --estimate_time_offset, --time_offset_search_s,
// --estimate_odometry_intrinsics, --wheel_track_m (echoed in `options`).
const OptionTable<SystematicsEstimationOptions>& SystematicsFlags();

// Registers the tables above, in the order of docs/cli.md, bound to
// `inputs`: after parsing, `inputs` holds every value given.
void AddCalibrationFlags(CLI::App* app, CalibrateInputs* inputs);

// The echo of the association and calibration flags, for
// ReportContext::flag_echo: {"inputs": {...}, "options": {...}}.
nlohmann::json CalibrationFlagsEcho(
    const AssociationOptions& association,
    const CalibrationOptions& calibration,
    const SystematicsEstimationOptions& systematics = {});

}  // namespace odomcal
