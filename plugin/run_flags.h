// The flags of `odomcal run` beyond the project and calibration flags, as
// tables (option_table.h): COLMAP, matching, frame selection and the mapper
// policy. Echoed in the result's `options.run`, --image_path in `inputs`.
#pragma once

#include "odomcal/plugin/option_table.h"
#include "odomcal/plugin/run_command.h"

#include <CLI/CLI.hpp>

namespace odomcal {

// --image_path and --workspace_path (where the outputs go: not echoed).
const OptionTable<RunSettings>& RunFolderFlags();
// Everything else `odomcal run` takes for itself.
const OptionTable<RunSettings>& RunFlags();

// Registers both tables, bound to `settings`.
void AddRunFlags(CLI::App* app, RunSettings* settings);

// The echo of `settings`: {"inputs": {"image_path": ...}, "options": {"run":
// {...}}}.
nlohmann::json RunFlagsEcho(const RunSettings& settings);

}  // namespace odomcal
