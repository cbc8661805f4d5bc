// The parameter sweeps of Fig. 2 in Guo, Mirzaei & Roumeliotis (ICRA 2012),
// as `odomcal simulate` runs them. The paper gives the ranges (odometry
// rotation noise SD 0-0.4 rad, translation noise SD proportional to the
// motion length, image noise 0-2 px at f = 400 px, the number of motions) but
// not the points nor the nominal values of the parameters not swept; ours:
//
//   nominal: 20 motions, odometry yaw SD 0.05 rad, odometry translation SD
//            5 % of the motion length, 1 px image noise (parametric mode:
//            camera rotation SD 0.005 rad, direction SD 0.02 rad at 1 px)
//   rotation_noise     odometry yaw SD [rad]        0, 0.05, ..., 0.4
//   translation_noise  odometry translation SD [fraction of length]
//                      0, 0.02, 0.05, 0.1, 0.15, 0.2
//   pixel_noise        image noise SD [px]          0, 0.25, 0.5, 1, 1.5, 2
//   num_motions        number of motions            5, 10, 20, 50, 100
//
// In parametric camera mode, the pixel_noise value multiplies the nominal
// camera rotation and direction SDs (1 px = nominal).
#pragma once

#include "odomcal/datasets/paper/paper_simulation.h"

#include <string>
#include <vector>

namespace odomcal {

struct PaperSweep {
  std::string name;     // rotation_noise, translation_noise, pixel_noise, ...
  std::string x_label;  // axis label with unit
  std::vector<double> values;
};

// The four sweeps above, in that order.
std::vector<PaperSweep> PaperSweeps();

// The sweep of that name; throws std::invalid_argument for an unknown name.
PaperSweep FindPaperSweep(const std::string& name);

// Nominal simulation options for a camera noise mode.
PaperSimulationOptions NominalPaperSimulation(CameraNoiseMode mode);

// `nominal` with the swept parameter set to `value`; throws
// std::invalid_argument for an unknown sweep name.
PaperSimulationOptions ApplySweepValue(const PaperSimulationOptions& nominal,
                                       const std::string& sweep_name,
                                       double value);

}  // namespace odomcal
