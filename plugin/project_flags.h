// Flags shared by the commands that calibrate a COLMAP project
// (`odomcal colmap`, `odomcal run`), and the output-folder rules.
#pragma once

#include "odomcal/plugin/cli_flags.h"
#include "odomcal/plugin/colmap_calibration.h"
#include "odomcal/plugin/option_table.h"
#include "odomcal/plugin/output_folder.h"
#include "odomcal/plugin/output_guard.h"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace odomcal {

// `odomcal colmap`'s --model_path and --database_path (echoed in `inputs`
// for `odomcal run` too, which sets them to its workspace's).
const OptionTable<ColmapCalibrationInputs>& ColmapModelFlags();
// --odometry, --image_timestamps, --file_name_time_unit (echoed in
// `inputs`).
const OptionTable<ColmapCalibrationInputs>& ProjectInputFlags();
// The stretch check's --min_inconsistent_run_pairs (echoed in `options`).
const OptionTable<StretchOptions>& StretchFlags();

struct ProjectFlags {
  CalibrateInputs calibrate;  // the calibration flags (cli_flags.h)
};

// ProjectInputFlags(), StretchFlags() and the calibration flags.
void AddProjectFlags(CLI::App* app,
                     ColmapCalibrationInputs* inputs,
                     ProjectFlags* flags);

// Copies the calibration flags into `inputs`.
void FinishProjectFlags(const ProjectFlags& flags,
                        ColmapCalibrationInputs* inputs);

// The echo of `odomcal colmap`'s flags as `inputs` holds them, for
// ProjectReportContext: the calibration flags, --model_path and
// --database_path (null when not given), the project inputs and the stretch
// check's flags.
nlohmann::json ProjectFlagsEcho(const ColmapCalibrationInputs& inputs);

// Checks the output folder `output` against `inputs` (output_guard.h), then
// creates it if needed and claims `entries` in it (output_folder.h), before
// any work. Throws OutputError.
void PrepareOutputFolder(const FlaggedPath& output,
                         const std::vector<FlaggedPath>& inputs,
                         const std::vector<std::string>& entries,
                         ExistingOutputs existing);

}  // namespace odomcal
