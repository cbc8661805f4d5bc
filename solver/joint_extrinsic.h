// The joint adjustment's extrinsic (joint_adjustment.h) taken into a
// calibration result, and how far it lies from the two-step one.
#pragma once

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

// One extrinsic quantity on which the two estimates differ by more than
// 3 of the two-step's standard deviations: the joint estimate lies outside
// the two-step's own 3-sigma interval, which the two-step's uncertainty
// promised it would not (most of the time).
struct ExtrinsicDisagreement {
  std::string quantity;          // "roll", "pitch", "yaw", "translation_x", ...
  double difference = 0.0;       // joint - two-step; deg or m
  double two_step_stddev = 0.0;  // deg or m
};

// The disagreements of `joint` (rotation as roll/pitch/yaw, x, y) with the
// two-step estimate and its covariance ([rx, ry, rz, tx, ty] leading block).
std::vector<ExtrinsicDisagreement> ExtrinsicDisagreements(
    const Rigid3d& joint,
    const Rigid3d& two_step,
    const Eigen::Matrix<double, 5, 5>& two_step_covariance);

}  // namespace odomcal
