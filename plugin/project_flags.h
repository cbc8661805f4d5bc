// Flags shared by the commands that calibrate a COLMAP project
// (`odomcal colmap`, `odomcal run`), and the output-folder rules.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "odomcal/plugin/cli_flags.h"
#include "odomcal/plugin/colmap_calibration.h"

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
void FinishProjectFlags(const ProjectFlags& flags, ColmapCalibrationInputs* inputs);

// Creates `output_dir` if needed. Throws OutputError when it holds files and
// !overwrite, or when it lies inside one of `protected_paths` (the user's
// input project: it is never written to).
void PrepareOutputFolder(const std::string& output_dir,
                         bool overwrite,
                         const std::vector<std::string>& protected_paths);

}  // namespace odomcal
