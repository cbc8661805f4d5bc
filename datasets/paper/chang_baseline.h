// The minimal odometer-camera calibration of Chang, Lebegue & Aggarwal,
// "Calibrating a mobile camera's parameters", Pattern Recognition 26(1),
// 1993 ("CM"), as Guo, Mirzaei & Roumeliotis (ICRA 2012) describe it in their
// Sections II and V, adapted to relative motions. Used as the baseline of the
// paper's evaluation; CalibrateOdomCam() is the method to use.
//
// Our reading of the method:
//  * Step 1 uses ONE robot motion and the camera rotation over it: the
//    camera's rotation axis k_B must be mapped onto the odometry z axis, with
//    the sign that makes the rotation angles agree: R k_B = sign(yaw_A) e_z.
//    This fixes two rotational degrees of freedom (q_yz is the smallest
//    rotation taking k_B there); rotation about z stays free.
//  * Step 2 determines the third rotational DoF and x, y from a minimal set
//    of motions. Chang et al. use the bearings of one landmark from three
//    poses; our input is relative motions whose translations are known up to
//    the scale, so the minimal set is two motions and the unknowns
//    (p_x, p_y, s cos(alpha), s sin(alpha)) follow from 4 linear equations —
//    the same algebra as the paper's step 2, without least squares.
//  * As the paper does, RANSAC picks the subset: each hypothesis draws the
//    step-1 motion and the two step-2 motions; the best hypothesis by the MSAC
//    score of hand_eye_ransac.h is the CM estimate. It is NOT re-fitted on its
//    inliers: CM cannot use more than the minimal measurements, which is what
//    the comparison is about. Scales of other segments: medians, as in RANSAC.
#pragma once

#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/rigid3.h"

#include <string>
#include <vector>

namespace odomcal {

struct ChangEstimate {
  bool success = false;
  std::string failure;
  Rigid3d odom_from_cam;
  std::vector<double> metric_scales;
  std::vector<char> inlier_mask;  // of the chosen hypothesis
  int num_iterations = 0;
};

// The minimal solution: step 1 from `axis_pair`, step 2 from the two pairs
// (same segment). False when a step is degenerate (no rotation in
// axis_pair, parallel translations).
bool SolveChangMinimal(const MotionPair& axis_pair,
                       const MotionPair& first,
                       const MotionPair& second,
                       double fixed_translation_z_m,
                       Rigid3d* odom_from_cam,
                       double* metric_scale);

// RANSAC over minimal samples; uses the RANSAC and noise settings of
// `options` (iteration limits, thresholds, seed).
ChangEstimate EstimateOdomFromCamChang(const MotionPairs& pairs,
                                       const CalibrationOptions& options);

}  // namespace odomcal
