#include "odomcal/solver/hand_eye_residual.h"

#include "odomcal/solver/angles.h"
#include "odomcal/solver/planarity_check.h"

#include <Eigen/Cholesky>

#include <cmath>

namespace odomcal {
namespace {

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d s;
  s << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return s;
}

}  // namespace

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

namespace {

MotionCovariance OdometryNoiseCovariance(const MotionPair& pair,
                                         const NoiseModel& noise) {
  if (pair.odom_covariance) {
    return *pair.odom_covariance;
  }
  const double yaw =
      std::abs(LogRotation(pair.odom_i_from_odom_j.rotation).z());
  const double yaw_sigma =
      noise.odom_yaw_sigma_deg * kDegToRad + noise.odom_yaw_sigma_rel * yaw;
  const double tilt_sigma = noise.odom_tilt_sigma_deg * kDegToRad;
  const double length = pair.odom_i_from_odom_j.translation.norm();
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

}  // namespace

MotionCovariance OdometryCovariance(const MotionPair& pair,
                                    const NoiseModel& noise) {
  MotionCovariance covariance = OdometryNoiseCovariance(pair, noise);
  if (pair.odom_interpolation_covariance) {
    covariance += *pair.odom_interpolation_covariance;
  }
  return covariance;
}

MotionCovariance CameraCovariance(const MotionPair& pair,
                                  const NoiseModel& noise) {
  if (pair.cam_covariance) {
    return *pair.cam_covariance;
  }
  const double r_sigma = noise.cam_rotation_sigma_deg * kDegToRad;
  const Eigen::Vector3d& t = pair.cam_i_from_cam_j.translation;
  const double length = t.norm();
  const double across = noise.cam_translation_sigma_rel * length;
  const double along = noise.CamTranslationAlongSigmaRel() * length;
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
  const Eigen::Matrix3d r_a =
      pair.odom_i_from_odom_j.rotation.toRotationMatrix();
  const Eigen::Matrix3d r = odom_from_cam.rotation.toRotationMatrix();
  Matrix6d f_a = Matrix6d::Zero();
  f_a.topLeftCorner<3, 3>() = -r_a.transpose();
  f_a.bottomLeftCorner<3, 3>() = -Skew(r_a * odom_from_cam.translation);
  f_a.bottomRightCorner<3, 3>().setIdentity();
  Matrix6d f_b = Matrix6d::Zero();
  f_b.topLeftCorner<3, 3>() = r_a.transpose() * r;
  f_b.bottomRightCorner<3, 3>() = -metric_scale * r;
  return f_a * OdometryCovariance(pair, noise) * f_a.transpose() +
         f_b * CameraCovariance(pair, noise) * f_b.transpose();
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
