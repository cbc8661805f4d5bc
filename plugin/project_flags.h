// Flags shared by the commands that calibrate a COLMAP project
// (`odomcal colmap`, `odomcal run`), and the output-folder rules.
#pragma once

#include "odomcal/plugin/cli_flags.h"
#include "odomcal/plugin/colmap_calibration.h"
#include "odomcal/plugin/output_folder.h"
#include "odomcal/plugin/output_guard.h"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace odomcal {

struct ProjectFlags {
  CalibrationFlags calibration;
  CalibrateInputs calibrate;  // association + calibration options
  std::string file_name_time_unit = "auto";
};

// --odometry, --image_timestamps, --file_name_time_unit, the calibration
// flags and the stretch check's --min_inconsistent_run_pairs.
void AddProjectFlags(CLI::App* app,
                     ColmapCalibrationInputs* inputs,
                     ProjectFlags* flags);

// Converts the text flags into `inputs`; throws std::invalid_argument.
void FinishProjectFlags(const ProjectFlags& flags,
                        ColmapCalibrationInputs* inputs);

// Checks the output folder `output` against `inputs` (output_guard.h), then
// creates it if needed and claims `entries` in it (output_folder.h), before
// any work. Throws OutputError.
void PrepareOutputFolder(const FlaggedPath& output,
                         const std::vector<FlaggedPath>& inputs,
                         const std::vector<std::string>& entries,
                         ExistingOutputs existing);

}  // namespace odomcal
