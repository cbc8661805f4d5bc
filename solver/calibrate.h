// Odometer-camera extrinsic calibration: the whole pipeline on motion pairs.
//
//   1. validate the input (non-finite values and negative segment indices
//      throw std::invalid_argument) and measure excitation and consistency;
//   2. select pairs: RANSAC (hand_eye_ransac.h) or all of them;
//   3. closed form, ALSP or ALS (hand_eye_linear.h), on the selected pairs;
//   4. Ceres refinement (hand_eye_refine.h), unless disabled;
//   5. covariance from the Fisher information under the noise model, and the
//      observability verdict: quantities whose standard deviation exceeds
//      the options' limits (or that lie in the information's null space) are
//      marked undetermined in `observability` and the status becomes
//      kUnobservable;
//   6. post-fit residuals; residuals that contradict the model (e.g. a wrong
//      pose convention) give kInconsistentData.
//
// Translation along the odometry z axis is unobservable under planar motion
// (Guo et al., Section IV-B): it is held at options.fixed_translation_z_m
// (observability.translation_z == kHeld). When the odometry is SE(3) and
// tilts (some rotation not about z), step 4 is repeated with z free, from
// the 3-D linear translation step (SolveTranslationScale3d); z is then
// estimated, with its standard deviation, when the information determines it
// within options.max_translation_stddev_m (the rotation axes are not all
// parallel), and held otherwise. Never prints, never aborts.
#pragma once

#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/calibration_result.h"
#include "odomcal/solver/motion_pair.h"

namespace odomcal {

CalibrationResult CalibrateOdomCam(const MotionPairs& pairs,
                                   const CalibrationOptions& options);

}  // namespace odomcal
