// The odometry log a command's inputs name, read the one way every command
// reads it. CalibrateInputs (odomcal calibrate, Python calibrate) and
// ColmapCalibrationInputs (odomcal colmap and run, Python
// calibrate_colmap and reconstruct_and_calibrate) both hold odometry_path,
// odometry_format, odometry_time_unit, odometry_time_unit_given and
// systematics (the wheel track and ticks per metre of a wheel-travel log).
#pragma once

#include "odomcal/adapters/systematics_estimation.h"
#include "odomcal/adapters/trajectory.h"
#include "odomcal/adapters/trajectory_io.h"

namespace odomcal {

// ReadOdometry of `inputs`' odometry; throws FormatError as it does.
template <typename Inputs>
Trajectory ReadOdometryOf(const Inputs& inputs) {
  return ReadOdometry(inputs.odometry_path,
                      inputs.odometry_format,
                      inputs.odometry_time_unit,
                      inputs.odometry_time_unit_given,
                      WheelTravelOptionsOf(inputs.systematics));
}

}  // namespace odomcal
