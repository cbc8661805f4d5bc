// The flags of `odomcal run` beyond the project and calibration flags, as
// tables (option_table.h) bound to ReconstructionOptions
// (reconstruction_pipeline.h): COLMAP, matching, frame selection and the
// mapper policy. Echoed in the result's `options.run`, --image_path in
// `inputs`. No CLI11 here: the command line registers the flags
// (command_flags.h).
#pragma once

#include "odomcal/plugin/colmap/reconstruction_pipeline.h"
#include "odomcal/plugin/options/option_table.h"

#include <nlohmann/json.hpp>

namespace odomcal {

// --image_path and --workspace_path (where the outputs go: not echoed).
const OptionTable<ReconstructionOptions>& RunFolderFlags();
// Everything else `odomcal run` takes for itself.
const OptionTable<ReconstructionOptions>& RunFlags();

// The echo of `settings`' own flags: {"inputs": {"image_path": ...},
// "options": {"run": {...}}}, as given: an automatic frame spacing is echoed
// as "auto" (a result echoes the values used: RunResultFlagsEcho).
nlohmann::json RunFlagsEcho(const ReconstructionOptions& settings);

// The echo of a finished `odomcal run` (CLI and Python alike): the project's
// flags with the model and database the pipeline made (null when it refused
// the drive before COLMAP), and the run's own flags with the frame spacing
// as used ("auto" resolved to numbers).
nlohmann::json RunResultFlagsEcho(const ReconstructionOptions& options,
                                  const ReconstructionResult& result);

}  // namespace odomcal
