// The joint adjustment's extrinsic (joint_adjustment.h) taken into a
// calibration result, and how far it lies from the two-step one.
#pragma once

#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/calibration_result.h"
#include "odomcal/solver/joint_adjustment.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace odomcal {

// Replaces result's rotation and translation x/y by the adjustment's and
// the covariance's extrinsic block [rx, ry, rz, tx, ty] by the adjustment's
// marginal one. The adjustment has no metric scale: the scales, their
// variances and translation z stay the two-step's, their cross terms with
// the extrinsic are dropped. The standard deviations are derived again.
// result must hold a covariance (the two-step calibration succeeded).
void AdoptJointExtrinsic(const JointAdjustmentResult& joint,
                         CalibrationResult* result);

// The adopted estimate must determine the extrinsic within the limits the
// two-step calibration is held to (limits.max_rotation_stddev_deg on the
// rotation axes, max_translation_stddev_m on x and y): an adjustment
// adopted where the images contradict the two-step may itself be too loose
// to use (on a road drive whose turns COLMAP folded, its jackknife left x
// and y known to 0.5-0.8 m). Where it is not, result becomes kUnobservable
// with the quantities undetermined and named in the message with their
// standard deviations; else it is left as it is. Call after
// AdoptJointExtrinsic.
void RefuseLooseAdoptedExtrinsic(const CalibrationOptions& limits,
                                 CalibrationResult* result);

// One extrinsic quantity of the two estimates and their standard
// deviations. Both rest on the same images and odometry, the adjustment on
// more of them, so the variance of their difference is taken as at most the
// sum of the two (it is the two-step's alone where the adjustment is much
// the more precise, the usual case; the adjustment's where it is the
// less precise, as with few points per image).
struct ExtrinsicDisagreement {
  std::string quantity;          // "roll", "pitch", "yaw", "translation_x", ...
  double difference = 0.0;       // joint - two-step; deg or m
  double two_step_stddev = 0.0;  // deg or m
  double joint_stddev = 0.0;     // deg or m
  // |difference| over the standard deviation of the difference.
  double Sigmas() const;
};

// The quantities (rotation as roll/pitch/yaw, x, y) on which `joint` and
// the two-step estimate differ by more than `min_sigmas` standard
// deviations of their difference (0: all five, in that order); the
// covariances are the [rx, ry, rz, tx, ty] blocks. Beyond 3 the joint
// estimate lies outside the two estimates' 3-sigma interval of agreement,
// which their uncertainties promised it would not (most of the time).
std::vector<ExtrinsicDisagreement> ExtrinsicDisagreements(
    const Rigid3d& joint,
    const Eigen::Matrix<double, 5, 5>& joint_covariance,
    const Rigid3d& two_step,
    const Eigen::Matrix<double, 5, 5>& two_step_covariance,
    double min_sigmas = 3.0);

}  // namespace odomcal
