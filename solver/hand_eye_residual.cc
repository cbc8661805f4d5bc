#include "odomcal/solver/hand_eye_residual.h"

#include "odomcal/solver/angles.h"
#include "odomcal/solver/planarity_check.h"

#include <Eigen/Cholesky>

#include <cmath>

namespace odomcal {
namespace {}  // namespace

Vector6d HandEyeResidual(const MotionPair& pair,
                         const Rigid3d& odom_from_cam,
                         double metric_scale) {
  const Eigen::Quaterniond& q = odom_from_cam.rotation;
  const Eigen::Vector3d& p = odom_from_cam.translation;
  const Rigid3d& a = pair.odom_i_from_odom_j;
  const Rigid3d& b = pair.cam_i_from_cam_j;
  Vector6d residual;
  residual.head<3>() =
      LogRotation(a.rotation.conjugate() * q * b.rotation * q.conjugate());
  residual.tail<3>() =
      a.rotation * p + a.translation - metric_scale * (q * b.translation) - p;
  return residual;
}

MotionCovariance OdometryNoiseCovariance(const MotionPair& pair,
                                         const NoiseModel& noise,
                                         const StepSize& step) {
  if (pair.odom_covariance) {
    return *pair.odom_covariance;
  }
  const double yaw_sigma = noise.odom_yaw_sigma_deg * kDegToRad +
                           noise.odom_yaw_sigma_rel * step.odometry_yaw_rad;
  const double tilt_sigma = noise.odom_tilt_sigma_deg * kDegToRad;
  const double length = step.odometry_length_m;
  const double t_sigma = noise.odom_translation_sigma_m +
                         noise.odom_translation_sigma_rel * length;
  // A planar log's height is zero by construction: its error there is not a
  // share of the in-plane slip (the proportional part) but the constant part
  // and the ground's own slope over the step (the tilt noise). Modelled as
  // slip, a flat drive's height residuals came out smaller than predicted and
  // the estimated translation noise low (NEES 8-9 for 6, docs/statistics.md).
  double z_variance = t_sigma * t_sigma;
  if (IsPlanarMotion(pair.odom_i_from_odom_j)) {
    const double slope = tilt_sigma * length;
    z_variance =
        noise.odom_translation_sigma_m * noise.odom_translation_sigma_m +
        slope * slope;
  }
  MotionCovariance covariance = MotionCovariance::Zero();
  covariance.diagonal() << tilt_sigma * tilt_sigma, tilt_sigma * tilt_sigma,
      yaw_sigma * yaw_sigma, t_sigma * t_sigma, t_sigma * t_sigma, z_variance;
  return covariance;
}

namespace {

// The inverse-variance mean of a measurement and a prediction of it; the
// measurement where neither has a variance.
double InverseVarianceMean(double measured,
                           double measured_variance,
                           double predicted,
                           double predicted_variance) {
  const double total = measured_variance + predicted_variance;
  if (!(total > 0.0) || !std::isfinite(total)) return measured;
  return (predicted_variance * measured + measured_variance * predicted) /
         total;
}

// The translation variance per axis a pair's own covariance states.
double OwnTranslationVariance(const MotionCovariance& covariance) {
  return covariance.bottomRightCorner<3, 3>().trace() / 3.0;
}

}  // namespace

StepSize MeasuredStep(const MotionPair& pair) {
  StepSize step;
  step.odometry_length_m = pair.odom_i_from_odom_j.translation.norm();
  step.odometry_yaw_rad =
      std::abs(LogRotation(pair.odom_i_from_odom_j.rotation).z());
  step.camera_length = pair.cam_i_from_cam_j.translation.norm();
  return step;
}

StepSize ModelledStep(const MotionPair& pair,
                      const Rigid3d& odom_from_cam,
                      double metric_scale,
                      const NoiseModel& noise) {
  const Rigid3d& a = pair.odom_i_from_odom_j;
  const Rigid3d& b = pair.cam_i_from_cam_j;
  const Eigen::Quaterniond& q = odom_from_cam.rotation;
  const Eigen::Vector3d& p = odom_from_cam.translation;
  StepSize measured = MeasuredStep(pair);
  if (!(metric_scale > 0.0) || !std::isfinite(metric_scale)) return measured;
  const double yaw_measured = LogRotation(a.rotation).z();
  // Each sensor's step predicted by the other under A X = X B(s).
  const double odometry_length_predicted =
      (metric_scale * (q * b.translation) + p - a.rotation * p).norm();
  const double camera_length_predicted =
      (a.translation + a.rotation * p - p).norm() / metric_scale;
  const double yaw_predicted = LogRotation(q * b.rotation * q.conjugate()).z();

  // Variances at the measured steps, in metres and radians.
  const double odometry_translation_sigma =
      noise.odom_translation_sigma_m +
      noise.odom_translation_sigma_rel * measured.odometry_length_m;
  const double odometry_translation_variance =
      pair.odom_covariance
          ? OwnTranslationVariance(*pair.odom_covariance)
          : odometry_translation_sigma * odometry_translation_sigma;
  const double camera_along_sigma = metric_scale *
                                    noise.CamTranslationAlongSigmaRel() *
                                    measured.camera_length;
  const double camera_translation_variance =
      pair.cam_covariance ? metric_scale * metric_scale *
                                OwnTranslationVariance(*pair.cam_covariance)
                          : camera_along_sigma * camera_along_sigma;
  const double yaw_sigma = noise.odom_yaw_sigma_deg * kDegToRad +
                           noise.odom_yaw_sigma_rel * measured.odometry_yaw_rad;
  const double odometry_yaw_variance = pair.odom_covariance
                                           ? (*pair.odom_covariance)(2, 2)
                                           : yaw_sigma * yaw_sigma;
  const double camera_rotation_sigma = noise.cam_rotation_sigma_deg * kDegToRad;
  const double camera_rotation_variance =
      pair.cam_covariance
          ? pair.cam_covariance->topLeftCorner<3, 3>().trace() / 3.0
          : camera_rotation_sigma * camera_rotation_sigma;

  StepSize step;
  step.odometry_length_m = InverseVarianceMean(measured.odometry_length_m,
                                               odometry_translation_variance,
                                               odometry_length_predicted,
                                               camera_translation_variance);
  step.camera_length =
      InverseVarianceMean(metric_scale * measured.camera_length,
                          camera_translation_variance,
                          metric_scale * camera_length_predicted,
                          odometry_translation_variance) /
      metric_scale;
  step.odometry_yaw_rad =
      std::abs(InverseVarianceMean(yaw_measured,
                                   odometry_yaw_variance,
                                   yaw_predicted,
                                   camera_rotation_variance));
  return step;
}

MotionCovariance OdometryCovariance(const MotionPair& pair,
                                    const NoiseModel& noise,
                                    const StepSize& step) {
  MotionCovariance covariance = OdometryNoiseCovariance(pair, noise, step);
  if (pair.odom_interpolation_covariance) {
    covariance += *pair.odom_interpolation_covariance;
  }
  return covariance;
}

MotionCovariance CameraCovariance(const MotionPair& pair,
                                  const NoiseModel& noise,
                                  const StepSize& step) {
  if (pair.cam_covariance) {
    return *pair.cam_covariance;
  }
  const double r_sigma = noise.cam_rotation_sigma_deg * kDegToRad;
  const Eigen::Vector3d& t = pair.cam_i_from_cam_j.translation;
  const double length = t.norm();
  const double across = noise.cam_translation_sigma_rel * step.camera_length;
  const double along = noise.CamTranslationAlongSigmaRel() * step.camera_length;
  MotionCovariance covariance = MotionCovariance::Zero();
  covariance.topLeftCorner<3, 3>().diagonal().setConstant(r_sigma * r_sigma);
  // across^2 (I - u u^T) + along^2 u u^T, u the direction of motion.
  covariance.bottomRightCorner<3, 3>().diagonal().setConstant(across * across);
  if (length > 0.0) {
    const Eigen::Vector3d u = t / length;
    covariance.bottomRightCorner<3, 3>() +=
        (along * along - across * across) * u * u.transpose();
  }
  return covariance;
}

Matrix6d HandEyeResidualCovariance(const MotionPair& pair,
                                   const Rigid3d& odom_from_cam,
                                   double metric_scale,
                                   const NoiseModel& noise) {
  return HandEyeResidualCovariance(
      pair,
      odom_from_cam,
      metric_scale,
      noise,
      ModelledStep(pair, odom_from_cam, metric_scale, noise));
}

namespace {

// Cov(r)'s odometry part F_A Sigma_A F_A^T and camera part F_B Sigma_B F_B^T.
struct ResidualCovarianceParts {
  Matrix6d odometry;
  Matrix6d camera;
};

ResidualCovarianceParts PartsOfResidualCovariance(const MotionPair& pair,
                                                  const Rigid3d& odom_from_cam,
                                                  double metric_scale,
                                                  const NoiseModel& noise,
                                                  const StepSize& step) {
  const ResidualNoiseJacobians f =
      HandEyeResidualNoiseJacobians(pair, odom_from_cam, metric_scale);
  return {
      f.odometry * OdometryCovariance(pair, noise, step) *
          f.odometry.transpose(),
      f.camera * CameraCovariance(pair, noise, step) * f.camera.transpose()};
}

}  // namespace

ResidualNoiseJacobians HandEyeResidualNoiseJacobians(
    const MotionPair& pair, const Rigid3d& odom_from_cam, double metric_scale) {
  const Eigen::Matrix3d r_a =
      pair.odom_i_from_odom_j.rotation.toRotationMatrix();
  const Eigen::Matrix3d r = odom_from_cam.rotation.toRotationMatrix();
  ResidualNoiseJacobians f;
  f.odometry.setZero();
  f.odometry.topLeftCorner<3, 3>() = -r_a.transpose();
  f.odometry.bottomLeftCorner<3, 3>() =
      -CrossProductMatrix(r_a * odom_from_cam.translation);
  f.odometry.bottomRightCorner<3, 3>().setIdentity();
  f.camera.setZero();
  f.camera.topLeftCorner<3, 3>() = r_a.transpose() * r;
  f.camera.bottomRightCorner<3, 3>() = -metric_scale * r;
  return f;
}

Matrix6d HandEyeResidualCovariance(const MotionPair& pair,
                                   const Rigid3d& odom_from_cam,
                                   double metric_scale,
                                   const NoiseModel& noise,
                                   const StepSize& step) {
  const ResidualCovarianceParts parts =
      PartsOfResidualCovariance(pair, odom_from_cam, metric_scale, noise, step);
  return parts.odometry + parts.camera;
}

ResidualCovarianceInScale HandEyeResidualCovarianceInScale(
    const MotionPair& pair,
    const Rigid3d& odom_from_cam,
    double metric_scale,
    const NoiseModel& noise) {
  const ResidualCovarianceParts parts = PartsOfResidualCovariance(
      pair,
      odom_from_cam,
      metric_scale,
      noise,
      ModelledStep(pair, odom_from_cam, metric_scale, noise));
  const Matrix6d& camera = parts.camera;
  ResidualCovarianceInScale split;
  split.scale = metric_scale;
  split.fixed = parts.odometry;
  split.fixed.topLeftCorner<3, 3>() += camera.topLeftCorner<3, 3>();
  split.cross.setZero();
  split.cross.topRightCorner<3, 3>() = camera.topRightCorner<3, 3>();
  split.cross.bottomLeftCorner<3, 3>() = camera.bottomLeftCorner<3, 3>();
  split.quadratic.setZero();
  split.quadratic.bottomRightCorner<3, 3>() = camera.bottomRightCorner<3, 3>();
  return split;
}

Matrix6d HandEyeSqrtInformation(const MotionPair& pair,
                                const Rigid3d& odom_from_cam,
                                double metric_scale,
                                const NoiseModel& noise) {
  Matrix6d covariance =
      HandEyeResidualCovariance(pair, odom_from_cam, metric_scale, noise);
  covariance.diagonal().array() += 1e-12 * covariance.trace() + 1e-300;
  // Cov = L L^T  =>  Cov^-1 = L^-T L^-1, W = L^-1 (lower-triangular).
  const Eigen::LLT<Matrix6d> llt(covariance);
  return llt.matrixL().solve(Matrix6d::Identity());
}

}  // namespace odomcal
