// Sweep tables and the mapping of a sweep value onto the simulation options.

#include "odomcal/datasets/paper/paper_sweeps.h"

#include <cmath>
#include <stdexcept>

namespace odomcal {
namespace {

// Parametric camera noise at the nominal 1 px.
constexpr double kNominalCamRotationSigmaRad = 0.005;
constexpr double kNominalCamDirectionSigmaRad = 0.02;

}  // namespace

std::vector<PaperSweep> PaperSweeps() {
  return {
      {"rotation_noise",
       "odometry rotation noise SD [rad]",
       {0.0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4}},
      {"translation_noise",
       "odometry translation noise SD [fraction of length]",
       {0.0, 0.02, 0.05, 0.1, 0.15, 0.2}},
      {"pixel_noise", "image noise SD [px]", {0.0, 0.25, 0.5, 1.0, 1.5, 2.0}},
      {"num_motions", "number of motions", {5, 10, 20, 50, 100}},
  };
}

PaperSweep FindPaperSweep(const std::string& name) {
  for (const PaperSweep& sweep : PaperSweeps()) {
    if (sweep.name == name) return sweep;
  }
  throw std::invalid_argument(
      "unknown sweep '" + name +
      "' (rotation_noise, translation_noise, pixel_noise, num_motions)");
}

PaperSimulationOptions NominalPaperSimulation(CameraNoiseMode mode) {
  PaperSimulationOptions options;
  options.num_motions = 20;
  options.odom_yaw_sigma_rad = 0.05;
  options.odom_translation_sigma_rel = 0.05;
  options.camera_noise = mode;
  options.pixel_sigma = 1.0;
  options.cam_rotation_sigma_rad = kNominalCamRotationSigmaRad;
  options.cam_direction_sigma_rad = kNominalCamDirectionSigmaRad;
  return options;
}

PaperSimulationOptions ApplySweepValue(const PaperSimulationOptions& nominal,
                                       const std::string& sweep_name,
                                       double value) {
  PaperSimulationOptions options = nominal;
  if (sweep_name == "rotation_noise") {
    options.odom_yaw_sigma_rad = value;
  } else if (sweep_name == "translation_noise") {
    options.odom_translation_sigma_rel = value;
  } else if (sweep_name == "pixel_noise") {
    options.pixel_sigma = value;
    options.cam_rotation_sigma_rad = value * kNominalCamRotationSigmaRad;
    options.cam_direction_sigma_rad = value * kNominalCamDirectionSigmaRad;
  } else if (sweep_name == "num_motions") {
    options.num_motions = static_cast<int>(std::lround(value));
  } else {
    throw std::invalid_argument("unknown sweep '" + sweep_name + "'");
  }
  return options;
}

}  // namespace odomcal
