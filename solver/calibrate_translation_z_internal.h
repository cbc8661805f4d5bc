// Translation z from the motion, for CalibrateOdomCam (calibrate.cc): SE(3)
// odometry that determines z, and a held z as a prior where the motion
// informs it without determining it (docs/non_planar_motion.md).
// Internal: not installed.
#pragma once

#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/calibration_result.h"
#include "odomcal/solver/motion_pair.h"

#include <Eigen/Core>

#include <vector>

namespace odomcal::internal {

// True when some odometry rotation moves the z axis beyond the planar
// tolerance (the same as IsPlanarOdometry's): R_A e_z leaves e_z.
bool OdometryTilts(const MotionPairs& pairs, const std::vector<int>& used);

// The estimate with translation z free, for SE(3) odometry: the 3-D linear
// translation step at the current rotation, then the refinement with z as a
// parameter (or its information alone without refinement). Accepted only
// when the information determines z within options.max_translation_stddev_m;
// otherwise the result keeps z held (nothing changes) and this returns
// false. RANSAC chose `used` with z held: it left out pairs whose tilt shows
// a wrong z, and the ones it kept lean toward the held value, so the pairs
// are chosen again under the estimate with z (and `used` updated).
bool EstimateTranslationZ(const MotionPairs& pairs,
                          std::vector<int>* used_pairs,
                          const CalibrationOptions& options,
                          CalibrationResult* result,
                          Eigen::MatrixXd* information,
                          std::vector<int>* information_segments);

// SE(3) odometry that does not determine z: z estimated under its prior
// N(fixed_translation_z_m, translation_z_prior_sigma_m^2) from the result
// with z held, the pairs chosen again under that estimate as in
// EstimateTranslationZ. Kept when the data's information on z (the others
// free) is more than TranslationZPrior::kMovedInformationRatio of the
// prior's; then `information` is the data's with z last (the prior's is
// added after the widening for the estimated noise, which concerns the data
// alone). Otherwise nothing changes: the data's standard deviation of z is
// then above ten prior sigmas, and a held z wrong by one prior sigma moves x
// and y by under a tenth of their standard deviations with z free. Records
// the data's standard deviation of z.
void EstimateTranslationZUnderPrior(const MotionPairs& pairs,
                                    std::vector<int>* used_pairs,
                                    const CalibrationOptions& options,
                                    CalibrationResult* result,
                                    Eigen::MatrixXd* information,
                                    std::vector<int>* information_segments);

// The data's information on z with every other parameter free: the Schur
// complement of the last row and column. 0 where the others are singular.
double MarginalInformationOfLast(const Eigen::MatrixXd& information);

}  // namespace odomcal::internal
