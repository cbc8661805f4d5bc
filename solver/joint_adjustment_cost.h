// The joint adjustment's residuals as Ceres cost functors (internal: not
// installed; Ceres types stay out of the public headers). The model:
// joint_adjustment.h; the parameter blocks: joint_adjustment_internal.h.
#pragma once

#include "odomcal/solver/camera_projection.h"
#include "odomcal/solver/odometry_intrinsics.h"
#include "odomcal/solver/planar_pose.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <ceres/cost_function.h>

#include <cmath>

namespace odomcal::internal {

template <typename T>
T WrapAngle(const T& angle) {
  using std::atan2;
  using std::cos;
  using std::sin;
  return atan2(sin(angle), cos(angle));
}

// Reprojection residual of one observation (joint_adjustment.h), in pixel
// sigmas.
template <ProjectionModel kModel>
struct ReprojectionCost {
  ReprojectionCost(const Eigen::Vector2d& pixel, double pixel_sigma)
      : pixel_(pixel), inverse_sigma_(1.0 / pixel_sigma) {}

  template <typename T>
  bool operator()(const T* pose,
                  const T* quaternion,
                  const T* t_xy,
                  const T* t_z,
                  const T* point,
                  const T* params,
                  T* residual) const {
    using std::cos;
    using std::sin;
    // Into the odometry frame at this image.
    const T c = cos(pose[2]);
    const T s = sin(pose[2]);
    const T dx = point[0] - pose[0];
    const T dy = point[1] - pose[1];
    const Eigen::Matrix<T, 3, 1> in_odom(
        c * dx + s * dy, -s * dx + c * dy, point[2]);
    // Into the camera frame: cam_from_odom = Inverse(odom_from_cam).
    const Eigen::Map<const Eigen::Quaternion<T>> odom_from_cam_rotation(
        quaternion);
    const Eigen::Matrix<T, 3, 1> offset(t_xy[0], t_xy[1], t_z[0]);
    const Eigen::Matrix<T, 3, 1> in_cam =
        odom_from_cam_rotation.conjugate() * (in_odom - offset);
    T pixel[2];
    if (!ProjectToPixel<kModel>(params, in_cam.data(), pixel)) return false;
    residual[0] = (pixel[0] - T(pixel_[0])) * T(inverse_sigma_);
    residual[1] = (pixel[1] - T(pixel_[1])) * T(inverse_sigma_);
    return true;
  }

  Eigen::Vector2d pixel_;
  double inverse_sigma_;
};

// ReprojectionCost for the camera's model as a Ceres cost (for
// AddResidualBlock, which takes ownership).
ceres::CostFunction* ReprojectionCostFor(ProjectionModel model,
                                         const Eigen::Vector2d& pixel,
                                         double pixel_sigma);

// The reprojection residual in pixels at doubles, without a cost object.
// Parameters as ReprojectionCost's, in its order; false when the point
// cannot be projected.
bool ReprojectionResidualFor(ProjectionModel model,
                             const Eigen::Vector2d& pixel,
                             const double* const* parameters,
                             double* residual);

// The planar motion from pose i to pose j, in pose i's frame.
template <typename T>
void PlanarMotionBetween(const T* pose_i, const T* pose_j, T* motion) {
  using std::cos;
  using std::sin;
  const T c = cos(pose_i[2]);
  const T s = sin(pose_i[2]);
  const T dx = pose_j[0] - pose_i[0];
  const T dy = pose_j[1] - pose_i[1];
  motion[0] = c * dx + s * dy;
  motion[1] = -s * dx + c * dy;
  motion[2] = WrapAngle(pose_j[2] - pose_i[2]);
}

// Whitened odometry residual of one link: the poses' planar motion minus
// the measured one.
template <typename T>
void WhitenedLinkResidual(const T* pose_i,
                          const T* pose_j,
                          const T* measured,
                          const Eigen::Matrix3d& sqrt_information,
                          T* residual) {
  T motion[3];
  PlanarMotionBetween(pose_i, pose_j, motion);
  const Eigen::Matrix<T, 3, 1> difference(motion[0] - measured[0],
                                          motion[1] - measured[1],
                                          WrapAngle(motion[2] - measured[2]));
  Eigen::Map<Eigen::Matrix<T, 3, 1>> whitened(residual);
  whitened = sqrt_information.cast<T>() * difference;
}

// A link whose measurement is fixed.
struct OdometryLinkCost {
  OdometryLinkCost(const PlanarPose& measured,
                   const Eigen::Matrix3d& sqrt_information)
      : measured_(measured), sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* pose_i, const T* pose_j, T* residual) const {
    const T measured[3] = {
        T(measured_.x), T(measured_.y), T(measured_.yaw_rad)};
    WhitenedLinkResidual(pose_i, pose_j, measured, sqrt_information_, residual);
    return true;
  }

  PlanarPose measured_;
  Eigen::Matrix3d sqrt_information_;
};

// A link whose measurement is the logged odometry re-integrated with the
// intrinsics and the clock offset's change being refined
// (CorrectedOdometryMotion, solver/odometry_intrinsics.h).
struct SystematicOdometryLinkCost {
  SystematicOdometryLinkCost(const OdometrySamples& samples,
                             const Eigen::Matrix3d& sqrt_information,
                             double wheel_track_m)
      : samples_(samples),
        sqrt_information_(sqrt_information),
        wheel_track_m_(wheel_track_m) {}

  template <typename T>
  bool operator()(const T* pose_i,
                  const T* pose_j,
                  const T* intrinsics,
                  const T* offset_change_s,
                  T* residual) const {
    const PlanarMotion<T> motion = CorrectedOdometryMotion(
        samples_, intrinsics, offset_change_s[0], wheel_track_m_);
    const T measured[3] = {motion.x, motion.y, motion.yaw};
    WhitenedLinkResidual(pose_i, pose_j, measured, sqrt_information_, residual);
    return true;
  }

  OdometrySamples samples_;
  Eigen::Matrix3d sqrt_information_;
  double wheel_track_m_;
};

// Upper-triangular W with W^T W = covariance^-1; false when the covariance
// is not positive definite.
bool SqrtInformation(const Eigen::Matrix3d& covariance, Eigen::Matrix3d* w);

}  // namespace odomcal::internal
