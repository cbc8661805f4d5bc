// `odomcal run`: from an image folder and an odometry log to a calibration,
// with the pipeline of reconstruction_pipeline.h; this file is the command
// line: flags in, progress lines, summary and files out.
#pragma once

#include "odomcal/plugin/colmap/reconstruction_pipeline.h"
#include "odomcal/plugin/report/calibration_report.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace odomcal {

struct RunOutcome {
  ColmapCalibrationRun calibration;
  ReportContext context;  // for the summary
  // What was written in the workspace, as listed to the user
  // ("calibration.json", "sparse/", ...): only entries with content.
  std::vector<std::string> written_outputs;
};

// Claims the workspace, runs ReconstructAndCalibrate with its five stages'
// progress on stdout and writes the outputs of `odomcal colmap` in the
// workspace (only calibration.json when the drive is refused before COLMAP).
// `bag_echo`: the echo of the flags the pipeline does not take (`--bag`
// and its options, `--rig`), {"inputs": {...}, "options": {...}}, merged
// into the result's echo. Throws FormatError,
// OutputError, ColmapError or std::invalid_argument with a one-line message.
RunOutcome RunAndWriteOutputs(const ReconstructionOptions& options,
                              const std::string& command,
                              const nlohmann::json& bag_echo = nullptr);

// "a, b, c".
std::string JoinNames(const std::vector<std::string>& names);

int RunRun(int argc, char** argv);

}  // namespace odomcal
