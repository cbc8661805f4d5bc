// Before SfM: do the odometry's motions between the image times determine the
// calibration at all? A straight drive does not (no turn: the rotation and
// the x/y lever arm are free), and that is visible in the odometry within a
// second, where COLMAP would take minutes to find out.
//
// The rule is the calibration's own: the images are given the camera poses a
// perfect reconstruction would have (the odometry at each image time,
// through a nominal camera mount, at scale 1) and calibrated as `odomcal
// calibrate` and `odomcal colmap` calibrate (EstimateSystematics around
// CalibrateOdomCam: the clock offset and odometry intrinsics estimated with
// the extrinsic, whose uncertainty widens it), with one difference: the noise
// is the given noise model (the defaults unless flags change it), not
// estimated from the data. Exact poses would make the noise estimation claim
// the least noise it allows (a tenth of the given), and a quantity the real
// calibration finds undetermined (e.g. translation y of a drive whose turns
// all go one way) would pass. What the calibration refuses on these motions
// under the given noise (kNotEnoughMotion, kUnobservable: too few pairs, no
// or too few turns, a standard deviation above its limit), it refuses on a
// reconstruction of the same images as noisy as the model says, with the
// same reason; a reconstruction much quieter or noisier than the model can
// part from it (benchmarks/precheck_agreement, docs/colmap_checks.md). The
// excitation does not depend on the mount: the solver's thresholds are on
// the odometry yaw, and the information is that of the motions.
#pragma once

#include "odomcal/adapters/association.h"
#include "odomcal/adapters/systematics_estimation.h"
#include "odomcal/adapters/trajectory.h"
#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/calibration_result.h"

#include <cstdint>
#include <vector>

namespace odomcal {

struct ExcitationPrecheck {
  // Of the ideal camera poses: keyframes and motion pairs, as the
  // calibration after SfM would have them at best (at the offset the
  // systematics estimation ended at).
  AssociationResult association;
  // The calibration's verdict on the ideal motions, without its estimate
  // (which would only echo the nominal mount): status, message (the
  // calibration's reason), `observability`, warnings and the excitation
  // diagnostics (pairs, turns, yaw increments).
  CalibrationResult verdict;
  // False when the verdict is kNotEnoughMotion or kUnobservable: the data
  // cannot determine the calibration, whatever SfM makes of the images.
  bool determinable = true;
};

// `image_stamps_ns`: camera times of the images SfM would get (any order);
// odometry time = camera time + association.camera_time_offset_ns. Images
// outside the odometry or in its gaps take part in no pair, as after SfM.
// The options are the calibration's (calibration.estimate_noise is not
// used). Throws std::invalid_argument from the options' Check().
ExcitationPrecheck PrecheckExcitation(
    const std::vector<int64_t>& image_stamps_ns,
    const Trajectory& odometry,
    const AssociationOptions& association,
    const CalibrationOptions& calibration,
    const SystematicsEstimationOptions& systematics);

}  // namespace odomcal
