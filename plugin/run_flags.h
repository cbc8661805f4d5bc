// The flags of `odomcal run` beyond the project and calibration flags, as
// tables (option_table.h) bound to ReconstructionOptions
// (reconstruction_pipeline.h): COLMAP, matching, frame selection and the
// mapper policy. Echoed in the result's `options.run`, --image_path in
// `inputs`.
#pragma once

#include "odomcal/plugin/option_table.h"
#include "odomcal/plugin/reconstruction_pipeline.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

namespace odomcal {

// --image_path and --workspace_path (where the outputs go: not echoed).
const OptionTable<ReconstructionOptions>& RunFolderFlags();
// Everything else `odomcal run` takes for itself.
const OptionTable<ReconstructionOptions>& RunFlags();

// Registers both tables, bound to `settings` (not its `project`: the
// project flags are AddProjectFlags').
void AddRunFlags(CLI::App* app, ReconstructionOptions* settings);

// The echo of `settings`' own flags: {"inputs": {"image_path": ...},
// "options": {"run": {...}}}.
nlohmann::json RunFlagsEcho(const ReconstructionOptions& settings);

}  // namespace odomcal
