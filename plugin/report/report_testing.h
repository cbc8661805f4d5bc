// Test-only: real runs of both calibrations on simulated drives, so that the
// report writers' tests check the outputs of real calibrations.
//   - WriteSimulatedColmapProject: a COLMAP project (one binary sub-model,
//     image times in image_timestamps.csv, an odometry CSV) for
//     CalibrateColmapProject, as `odomcal colmap` would read it;
//   - SimulatedCalibrationRun: what `odomcal calibrate` computes for a drive.
#pragma once

#include "odomcal/datasets/simulation/drive_simulator.h"
#include "odomcal/plugin/cli/calibrate_command.h"
#include "odomcal/plugin/colmap/colmap_calibration.h"

#include <cstdint>
#include <string>

namespace odomcal {

struct SimulatedColmapProjectOptions {
  uint64_t seed = 1;
  double duration_s = 40.0;
  // Images 100..129 of the sub-model bent out of the drive's path, as when
  // COLMAP folds a stretch: the odometry contradicts them.
  bool fold = false;
  // The folded images are the sub-model's last 30 instead (the fold reaches
  // its end).
  bool fold_at_end = false;
  // Image of the sub-model (by index; -1: none) registered rotated by 100 deg
  // about the camera's x axis and 0.5 m off, as COLMAP misregisters one
  // image of a stretch it otherwise gets right.
  int misregistered_image = -1;
  // Noise of each camera pose (the drive simulator's; deg, and its position
  // noise scaled alike from 0.0005 at 0.01 deg).
  double camera_rotation_noise_deg = 0.01;
  // COLMAP-like scale drift: the metric scale (m/unit) of the camera
  // positions grows linearly by this fraction from the first image to the
  // last (each step divided by the scale at its time), as an incremental
  // reconstruction's does.
  double scale_drift = 0.0;
  // Points seen by the images: this many new points per image, 2 to 8 m
  // ahead of its camera, each observed (0.5 px noise) in the images that
  // see it among the next 20 (PINHOLE 320 x 240, COLMAP's pixel
  // convention: a feature track) and placed in
  // the model through its first image's pose (so that the model carries
  // the scale drift locally, as COLMAP's does). 0: a model without points.
  int points_per_image = 0;
};

// True metric scale of image `index` of a project written with `options`
// (drive.metric_scale times the drift's growth at that image).
double SimulatedImageMetricScale(const SimulatedColmapProjectOptions& options,
                                 size_t index,
                                 size_t num_images);

// Writes the project under `dir` (created) and returns the inputs of
// CalibrateColmapProject for it (fixed translation z: 0.4 m, the truth).
// `drive` (optional) receives the simulated drive, with its truth.
ColmapCalibrationInputs WriteSimulatedColmapProject(
    const std::string& dir,
    const SimulatedColmapProjectOptions& options,
    SimulatedDrive* drive = nullptr);

// `odomcal calibrate` on a simulated drive, in memory; straight_only gives a
// drive that determines neither rotation nor x/y (status unobservable).
CalibrationRun SimulatedCalibrationRun(uint64_t seed, bool straight_only);

}  // namespace odomcal
