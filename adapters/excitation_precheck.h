// Before SfM: do the odometry's motions between the image times determine the
// calibration at all? A straight drive does not (no turn: the rotation and
// the x/y lever arm are free), and that is visible in the odometry within a
// second, where COLMAP would take minutes to find out.
//
// The rule is the solver's own: the images are given the camera poses a
// perfect reconstruction would have (the odometry at each image time,
// through a nominal camera mount, at scale 1), associated with the odometry
// as `odomcal colmap` associates registered images (association.h), and
// calibrated with CalibrateOdomCam. What it refuses on these ideal motions
// (kNotEnoughMotion, kUnobservable: too few pairs, no or too few turns,
// turns that do not separate the lever arm from the scale) no real
// reconstruction of the same images can make determined. The excitation
// does not depend on the mount: the solver's thresholds are on the odometry
// yaw, and the information is that of the motions.
#pragma once

#include "odomcal/adapters/association.h"
#include "odomcal/adapters/trajectory.h"
#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/calibration_result.h"

#include <cstdint>
#include <vector>

namespace odomcal {

struct ExcitationPrecheck {
  // Of the ideal camera poses: keyframes and motion pairs, as the
  // calibration after SfM would have them at best.
  AssociationResult association;
  // The solver's verdict on the ideal motions, without its estimate (which
  // would only echo the nominal mount): status, message, `observability`,
  // warnings and the excitation diagnostics (pairs, turns, yaw increments).
  CalibrationResult verdict;
  // False when the verdict is kNotEnoughMotion or kUnobservable: the data
  // cannot determine the calibration, whatever SfM makes of the images.
  bool determinable = true;
};

// `image_stamps_ns`: camera times of the images SfM would get (any order);
// odometry time = camera time + association.camera_time_offset_ns. Images
// outside the odometry or in its gaps take part in no pair, as after SfM.
// Throws std::invalid_argument from the options' Check().
ExcitationPrecheck PrecheckExcitation(
    const std::vector<int64_t>& image_stamps_ns,
    const Trajectory& odometry,
    const AssociationOptions& association,
    const CalibrationOptions& calibration);

}  // namespace odomcal
