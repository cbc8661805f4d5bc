// `odomcal run`: from an image folder and an odometry log to a calibration.
// Selects frames with the odometry, refuses a drive whose odometry cannot
// determine the calibration (no or too few turns) before COLMAP, runs COLMAP
// (feature_extractor, odometry-guided spatial or sequential matching, mapper,
// run again with another random seed while the odometry contradicts its model,
// matching again when that does not help) in a workspace, then calibrates the
// reconstruction as `odomcal colmap` does. Finished COLMAP stages are reused
// when rerun on the same workspace.
#pragma once

#include "odomcal/adapters/frame_selection.h"
#include "odomcal/plugin/colmap_calibration.h"

#include <string>

namespace odomcal {

struct RunSettings {
  std::string image_path;
  std::string workspace_path;
  std::string camera_model = "PINHOLE";
  std::string camera_params;  // COLMAP order, comma-separated; empty: estimate
  std::string matcher = "spatial";  // or "sequential"
  std::string colmap_path = "colmap";
  int max_num_features = 2048;
  int num_threads = 2;
  int spatial_neighbors = 8;
  int sequential_overlap = 10;
  int mapper_attempts = 3;  // at most, per matching; see mapper_attempts.h
  bool rematch = true;      // match again when the seeds do not help
  // Run COLMAP even when the odometry at the image times cannot determine
  // the calibration (excitation_precheck.h); otherwise that is refused
  // before any COLMAP stage, with the solver's status.
  bool force = false;
  FrameSelectionOptions frames;
};

// The five stages with progress on stdout; the workspace receives COLMAP's
// files and the outputs of `odomcal colmap`. `inputs` supplies the odometry,
// image times and calibration options (model and database paths are set
// here). Throws FormatError, OutputError, ColmapError or
// std::invalid_argument with a one-line message.
ColmapCalibrationRun RunReconstructionPipeline(const RunSettings& settings,
                                               ColmapCalibrationInputs inputs,
                                               const std::string& command);

int RunRun(int argc, char** argv);

}  // namespace odomcal
