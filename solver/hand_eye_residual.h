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

// The step sizes NoiseModel's proportional parts scale with.
struct StepSize {
  double odometry_length_m = 0.0;  // |t_A|
  double odometry_yaw_rad = 0.0;   // |yaw of R_A|
  double camera_length = 0.0;      // |t_B|, reconstruction units
};

// The pair's steps as measured, each sensor's by itself.
StepSize MeasuredStep(const MotionPair& pair);

// The pair's step as both sensors measure it, under the estimate: for each
// sensor, the inverse-variance mean of its own measurement and the other
// sensor's prediction of it (NoiseModel's variances at the measured steps).
// Sized by its own measurement, a pair's weight would follow its own noise:
// a step measured short weighs more, and the scale comes out low by many of
// its sigma at a few thousand pairs. The mean is uncorrelated, to first
// order, with the difference of the two, which the residual is.
StepSize ModelledStep(const MotionPair& pair,
                      const Rigid3d& odom_from_cam,
                      double metric_scale,
                      const NoiseModel& noise);

// The pair's odometry covariance, or the one NoiseModel implies at the
// step: the odometry's own noise.
MotionCovariance OdometryNoiseCovariance(const MotionPair& pair,
                                         const NoiseModel& noise,
                                         const StepSize& step);
// OdometryNoiseCovariance plus the pair's odom_interpolation_covariance.
MotionCovariance OdometryCovariance(const MotionPair& pair,
                                    const NoiseModel& noise,
                                    const StepSize& step);
// The pair's camera covariance (reconstruction units), or NoiseModel's at
// the step.
MotionCovariance CameraCovariance(const MotionPair& pair,
                                  const NoiseModel& noise,
                                  const StepSize& step);

// F_A and F_B of the file comment at the estimate: Cov(r) = F_A Sigma_A
// F_A^T + F_B Sigma_B F_B^T.
struct ResidualNoiseJacobians {
  Matrix6d odometry;  // F_A
  Matrix6d camera;    // F_B
};
ResidualNoiseJacobians HandEyeResidualNoiseJacobians(
    const MotionPair& pair, const Rigid3d& odom_from_cam, double metric_scale);

// Cov(r) at the given estimate, NoiseModel's parts sized by ModelledStep.
Matrix6d HandEyeResidualCovariance(const MotionPair& pair,
                                   const Rigid3d& odom_from_cam,
                                   double metric_scale,
                                   const NoiseModel& noise);
// Cov(r) with NoiseModel's parts sized by the given step (the noise
// estimation sizes each component's part by the full model's step).
Matrix6d HandEyeResidualCovariance(const MotionPair& pair,
                                   const Rigid3d& odom_from_cam,
                                   double metric_scale,
                                   const NoiseModel& noise,
                                   const StepSize& step);

// Cov(r) split by how it depends on the metric scale s: the camera's
// translation enters as -s R t_B, so Cov(r)(s') = fixed + (s' / s) cross +
// (s' / s)^2 quadratic about the scale s it was evaluated at (the rest of
// the estimate held). The refinement weighs each pair by Cov(r) at the
// scale it tries: weights held at the last scale would make the estimate
// the errors-in-variables one, attenuated by the camera's noise (a scale
// low by several of its sigma where the camera is noisy).
struct ResidualCovarianceInScale {
  Matrix6d fixed;
  Matrix6d cross;
  Matrix6d quadratic;
  double scale = 1.0;
};
ResidualCovarianceInScale HandEyeResidualCovarianceInScale(
    const MotionPair& pair,
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
