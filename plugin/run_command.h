// `odomcal run`: from an image folder and an odometry log to a calibration.
// Selects frames with the odometry, runs COLMAP (feature_extractor,
// odometry-guided spatial or sequential matching, mapper) in a workspace,
// then calibrates the reconstruction as `odomcal colmap` does. Finished
// COLMAP stages are reused when rerun on the same workspace.
#pragma once

namespace odomcal {

int RunRun(int argc, char** argv);

}  // namespace odomcal
