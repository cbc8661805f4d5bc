// Residual of one motion pair under a candidate extrinsic, and its
// first-order covariance; the batch cost of eq. (24) in Guo et al. sums the
// squared Mahalanobis norms of these residuals.
//
//   r_rot = Log(q_A^-1 ⊗ q ⊗ q_B ⊗ q^-1)            (radians, 3)
//   r_t   = R_A p + t_A - s R(q) t_B - p              (metres, 3)
// i.e. the rotation and translation parts of the mismatch between the two
// sides of  A X = X B(s)  with X = odom_from_cam = (q, p).
//
// Measurement model (also the simulator's): a measured rotation is
// Exp(n) R_true, n ~ N(0, Sigma_rot); a measured translation is t_true + n_t.
// To first order r = F_A n_A + F_B n_B with
//   F_A = [ -R_A^T         0 ]      F_B = [ R_A^T R    0    ]
//         [ -[R_A p]x      I ]            [ 0        -s R   ]
// and Cov(r) = F_A Sigma_A F_A^T + F_B Sigma_B F_B^T.
#pragma once

#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>

namespace odomcal {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

// [r_rot; r_t] as above.
Vector6d HandEyeResidual(const MotionPair& pair,
                         const Rigid3d& odom_from_cam,
                         double metric_scale);

// The pair's odometry covariance, or the one NoiseModel implies, plus the
// pair's odom_interpolation_covariance.
MotionCovariance OdometryCovariance(const MotionPair& pair,
                                    const NoiseModel& noise);
// The pair's camera covariance (reconstruction units), or NoiseModel's.
MotionCovariance CameraCovariance(const MotionPair& pair,
                                  const NoiseModel& noise);

// Cov(r) at the given estimate.
Matrix6d HandEyeResidualCovariance(const MotionPair& pair,
                                   const Rigid3d& odom_from_cam,
                                   double metric_scale,
                                   const NoiseModel& noise);

// Lower-triangular W with W^T W = Cov(r)^-1, so that W r ~ N(0, I). A tiny
// diagonal load keeps it finite when Cov(r) is (numerically) singular.
Matrix6d HandEyeSqrtInformation(const MotionPair& pair,
                                const Rigid3d& odom_from_cam,
                                double metric_scale,
                                const NoiseModel& noise);

}  // namespace odomcal
