// Analytical least-squares odometer-camera calibration (ALSP / ALS).
//
// C. X. Guo, F. M. Mirzaei, S. I. Roumeliotis, "An Analytical Least-Squares
// Solution to the Odometer-Camera Extrinsic Calibration Problem", ICRA 2012,
// Section IV, derived here for Hamilton quaternions (the paper uses JPL).
//
// Model, for every pair i with A_i = odom_i_from_odom_j (metres, rotation
// about z) and B_i = cam_i_from_cam_j (reconstruction units of segment k):
//   q_A ⊗ q = q ⊗ q_B                              (rotation)
//   (R_A - I) p = s_k R(q) t_B - t_A                 (translation)
// with X = odom_from_cam = (q, p) and s_k metres per reconstruction unit.
//
// Step 1. Write q = q_z(alpha) ⊗ q_yz, q_yz = q_y(beta) ⊗ q_z(gamma). Since
// q_A and q_z(alpha) commute, (L(q_A) - R(q_B)) q_yz = 0, where L and R are
// the Hamilton left/right product matrices in [w, x, y, z] order. q_yz lies
// in the span of the two eigenvectors of M^T M = sum_i (L - R)^T (L - R) with
// the smallest eigenvalues and satisfies w x = y z (from the definition of
// q_yz) and |q_yz| = 1. The constraint has two roots, which differ by a
// rotation of pi about z; step 2 absorbs that into alpha, the cheaper root is
// kept. When the camera z axis is parallel to the odometry z axis (beta = 0
// or pi) every vector of the span satisfies the constraint; any is correct.
//
// Step 2. With v_i the first two components of R(q_yz) t_B (ALSP: after
// projecting t_B onto the motion plane), minimise over p_x, p_y, alpha, s_k
//   sum_i | J_i [p_x p_y]^T - s_k Rz(alpha) v_i + t_A,xy |^2,
// J_i = top-left 2x2 of R_A - I. One segment: linear least squares in
// (p_x, p_y, s cos(alpha), s sin(alpha)) as in the paper. Several segments
// (one scale each, alpha shared): the linear problem in (p, s_k) is
// eliminated for every alpha (variable projection), the global minimum over
// alpha is bracketed on a fine grid and polished with Gauss-Newton on the
// residuals, which makes it exact to machine precision.
#pragma once

#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace odomcal {

struct LinearOptions {
  LinearMethod method = LinearMethod::kAlsp;
  PlaneProjection alsp_projection = PlaneProjection::kOrthogonal;
  double fixed_translation_z_m = 0.0;
};

struct LinearEstimate {
  bool success = false;
  std::string failure;  // why not, when !success

  Rigid3d odom_from_cam;
  // One per segment index 0..max over the used pairs; NaN for a segment
  // without used pairs.
  std::vector<double> metric_scales;
  double step2_cost = 0.0;  // sum of squared step-2 residuals, m^2

  Eigen::Vector4d rotation_step_eigenvalues = Eigen::Vector4d::Zero();
  double rotation_step_ratio = 0.0;
  bool rotation_step_gimbal = false;
  int num_constraint_roots = 0;
  double translation_step_condition_number = 0.0;
};

// Closed form on pairs[indices[0]], pairs[indices[1]], ...
LinearEstimate EstimateOdomFromCamLinear(const MotionPairs& pairs,
                                         const std::vector<int>& indices,
                                         const LinearOptions& options);
// Closed form on all pairs.
LinearEstimate EstimateOdomFromCamLinear(const MotionPairs& pairs,
                                         const LinearOptions& options);

// Step 1 alone: the unit q_yz candidates (one or two) satisfying w x = y z,
// and the eigen-analysis of M^T M written into `estimate`.
std::vector<Eigen::Quaterniond> SolveRotationYZ(const MotionPairs& pairs,
                                                const std::vector<int>& indices,
                                                LinearEstimate* estimate);

// Step 2 alone for a given q_yz: fills odom_from_cam, metric_scales and
// step2_cost of `estimate`; false (with estimate->failure) when singular.
bool SolveYawTranslationScale(const MotionPairs& pairs,
                              const std::vector<int>& indices,
                              const Eigen::Quaterniond& q_yz,
                              const LinearOptions& options,
                              LinearEstimate* estimate);

// The translation step in three dimensions for a known rotation, for SE(3)
// odometry whose rotation axes are not all parallel (then the z rows of
// (R_A - I) p = s_k R(q) t_B - t_A determine p_z too): linear least squares
// over p (3) and s_k on pairs[indices]. Fills odom_from_cam (rotation as
// given), metric_scales and translation_step_condition_number of the
// result; !success with `failure` when the step is singular (e.g. planar
// odometry, or all rotation axes parallel).
LinearEstimate SolveTranslationScale3d(const MotionPairs& pairs,
                                       const std::vector<int>& indices,
                                       const Eigen::Quaterniond& rotation);

// Hamilton product matrices, quaternions as [w, x, y, z]:
// p ⊗ q = QuaternionLeftMatrix(p) q = QuaternionRightMatrix(q) p.
Eigen::Matrix4d QuaternionLeftMatrix(const Eigen::Quaterniond& p);
Eigen::Matrix4d QuaternionRightMatrix(const Eigen::Quaterniond& q);

}  // namespace odomcal
