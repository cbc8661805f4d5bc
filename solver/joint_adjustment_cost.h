// The joint adjustment's residuals as Ceres cost functors (internal: not
// installed; Ceres types stay out of the public headers). The model:
// joint_adjustment.h; the parameter blocks: joint_adjustment_internal.h.
#pragma once

#include "odomcal/solver/camera_projection.h"
#include "odomcal/solver/odometry_intrinsics.h"
#include "odomcal/solver/planar_pose.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <ceres/cost_function.h>
#include <ceres/rotation.h>

#include <cmath>

namespace odomcal::internal {

template <typename T>
T WrapAngle(const T& angle) {
  using std::atan2;
  using std::cos;
  using std::sin;
  return atan2(sin(angle), cos(angle));
}

// A point in the origin frame into the odometry frame of a planar pose
// (x, y, yaw).
template <typename T>
Eigen::Matrix<T, 3, 1> PlanarOdomFromOrigin(const T* pose, const T* point) {
  using std::cos;
  using std::sin;
  const T c = cos(pose[2]);
  const T s = sin(pose[2]);
  const T dx = point[0] - pose[0];
  const T dy = point[1] - pose[1];
  return {c * dx + s * dy, -s * dx + c * dy, point[2]};
}

// The same for a whole pose: the planar block (x, y, yaw) and the tilt
// block (z, roll, pitch), origin_from_odom = (x, y, z) and
// Rz(yaw) Ry(pitch) Rx(roll).
template <typename T>
Eigen::Matrix<T, 3, 1> OdomFromOrigin(const T* pose,
                                      const T* tilt,
                                      const T* point) {
  using std::cos;
  using std::sin;
  const T shifted[3] = {point[0], point[1], point[2] - tilt[0]};
  // Rz^T, then Ry^T, then Rx^T.
  const Eigen::Matrix<T, 3, 1> q = PlanarOdomFromOrigin(pose, shifted);
  const T cp = cos(tilt[2]);
  const T sp = sin(tilt[2]);
  const T r0 = cp * q[0] - sp * q[2];
  const T r2 = sp * q[0] + cp * q[2];
  const T cr = cos(tilt[1]);
  const T sr = sin(tilt[1]);
  return {r0, cr * q[1] + sr * r2, -sr * q[1] + cr * r2};
}

// origin_from_odom's rotation of a whole pose (OdomFromOrigin's).
template <typename T>
Eigen::Matrix<T, 3, 3> OriginFromOdomRotation(const T* pose, const T* tilt) {
  using std::cos;
  using std::sin;
  const T cy = cos(pose[2]);
  const T sy = sin(pose[2]);
  const T cp = cos(tilt[2]);
  const T sp = sin(tilt[2]);
  const T cr = cos(tilt[1]);
  const T sr = sin(tilt[1]);
  Eigen::Matrix<T, 3, 3> r;
  r << cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr,  //
      sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,   //
      -sp, cp * sr, cp * cr;
  return r;
}

// A point in the odometry frame through odom_from_cam = (quaternion,
// [t_xy, t_z]) and the camera's projection, minus the observed pixel, in
// pixel sigmas.
template <ProjectionModel kModel, typename T>
bool ReprojectionFromOdom(const Eigen::Matrix<T, 3, 1>& in_odom,
                          const T* quaternion,
                          const T* t_xy,
                          const T* t_z,
                          const T* params,
                          const Eigen::Vector2d& observed,
                          double inverse_sigma,
                          T* residual) {
  // Into the camera frame: cam_from_odom = Inverse(odom_from_cam).
  const Eigen::Map<const Eigen::Quaternion<T>> odom_from_cam_rotation(
      quaternion);
  const Eigen::Matrix<T, 3, 1> offset(t_xy[0], t_xy[1], t_z[0]);
  const Eigen::Matrix<T, 3, 1> in_cam =
      odom_from_cam_rotation.conjugate() * (in_odom - offset);
  T pixel[2];
  if (!ProjectToPixel<kModel>(params, in_cam.data(), pixel)) return false;
  residual[0] = (pixel[0] - T(observed[0])) * T(inverse_sigma);
  residual[1] = (pixel[1] - T(observed[1])) * T(inverse_sigma);
  return true;
}

// Reprojection residual of one observation (joint_adjustment.h), in pixel
// sigmas, from a planar robot pose.
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
    return ReprojectionFromOdom<kModel>(PlanarOdomFromOrigin(pose, point),
                                        quaternion,
                                        t_xy,
                                        t_z,
                                        params,
                                        pixel_,
                                        inverse_sigma_,
                                        residual);
  }

  Eigen::Vector2d pixel_;
  double inverse_sigma_;
};

// The same from a whole robot pose (RobotMotionModel::kSE3): the pose's
// tilt block after its planar one.
template <ProjectionModel kModel>
struct TiltedReprojectionCost {
  TiltedReprojectionCost(const Eigen::Vector2d& pixel, double pixel_sigma)
      : pixel_(pixel), inverse_sigma_(1.0 / pixel_sigma) {}

  template <typename T>
  bool operator()(const T* pose,
                  const T* tilt,
                  const T* quaternion,
                  const T* t_xy,
                  const T* t_z,
                  const T* point,
                  const T* params,
                  T* residual) const {
    return ReprojectionFromOdom<kModel>(OdomFromOrigin(pose, tilt, point),
                                        quaternion,
                                        t_xy,
                                        t_z,
                                        params,
                                        pixel_,
                                        inverse_sigma_,
                                        residual);
  }

  Eigen::Vector2d pixel_;
  double inverse_sigma_;
};

// ReprojectionCost (TiltedReprojectionCost when `tilted`) for the camera's
// model as a Ceres cost (for AddResidualBlock, which takes ownership).
ceres::CostFunction* ReprojectionCostFor(ProjectionModel model,
                                         bool tilted,
                                         const Eigen::Vector2d& pixel,
                                         double pixel_sigma);

// The reprojection residual in pixels at doubles, without a cost object.
// Parameters as ReprojectionCost's (TiltedReprojectionCost's when
// `tilted`), in its order; false when the point cannot be projected.
bool ReprojectionResidualFor(ProjectionModel model,
                             bool tilted,
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

// A link of whole poses (RobotMotionModel::kSE3): the motion the poses
// imply, odom_i_from_odom_j = Inverse(pose_i) pose_j, against the measured
// one: [Log(R R_measured^T), t - t_measured], whitened (the order and the
// perturbation of OdometryMotion3d's covariance).
struct Se3OdometryLinkCost {
  Se3OdometryLinkCost(const Rigid3d& measured,
                      const Eigen::Matrix<double, 6, 6>& sqrt_information)
      : measured_rotation_(measured.rotation.toRotationMatrix()),
        measured_translation_(measured.translation),
        sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* pose_i,
                  const T* tilt_i,
                  const T* pose_j,
                  const T* tilt_j,
                  T* residual) const {
    const Eigen::Matrix<T, 3, 3> rotation_i =
        OriginFromOdomRotation(pose_i, tilt_i);
    const Eigen::Matrix<T, 3, 3> rotation_ij =
        rotation_i.transpose() * OriginFromOdomRotation(pose_j, tilt_j);
    const Eigen::Matrix<T, 3, 1> delta(
        pose_j[0] - pose_i[0], pose_j[1] - pose_i[1], tilt_j[0] - tilt_i[0]);
    const Eigen::Matrix<T, 3, 1> translation_ij =
        rotation_i.transpose() * delta;
    const Eigen::Matrix<T, 3, 3> difference =
        rotation_ij * measured_rotation_.cast<T>().transpose();
    Eigen::Matrix<T, 6, 1> error;
    ceres::RotationMatrixToAngleAxis(
        ceres::ColumnMajorAdapter3x3(difference.data()), error.data());
    error.template tail<3>() = translation_ij - measured_translation_.cast<T>();
    Eigen::Map<Eigen::Matrix<T, 6, 1>> whitened(residual);
    whitened = sqrt_information_.cast<T>() * error;
    return true;
  }

  Eigen::Matrix3d measured_rotation_;
  Eigen::Vector3d measured_translation_;
  Eigen::Matrix<double, 6, 6> sqrt_information_;
};

// The out-of-plane bounds of a planar log's link on ground that pitches
// and banks (RobotMotionModel::kOnGround): the standard deviation of the
// tilt change (rad, about x and y) and of the height (m, along the first
// pose's z) between the link's poses, from the ground's tilt rate g (rad per
// metre of travel) and the link's length L: g L and g L^2 / 2 (the chord of
// an arc that turns by g L), each with a floor for a link of no length.
struct GroundBounds {
  double tilt_sigma_rad = 0.0;
  double height_sigma_m = 0.0;
};
GroundBounds GroundBoundsOf(double tilt_rate_rad_per_m, double length_m);

// Whitened residual of a planar log's link between whole poses: the
// motion the poses imply, odom_i_from_odom_j (rotation vector phi,
// translation t), against the measured planar one: [t_x, t_y, phi_z] minus
// the measurement, whitened by its sqrt information; then phi_x, phi_y and
// t_z over the ground's bounds (the log does not measure them; the ground
// keeps them small).
template <typename T>
void GroundLinkResidual(const T* pose_i,
                        const T* tilt_i,
                        const T* pose_j,
                        const T* tilt_j,
                        const T* measured,
                        const Eigen::Matrix3d& sqrt_information,
                        const GroundBounds& bounds,
                        T* residual) {
  const Eigen::Matrix<T, 3, 3> rotation_i =
      OriginFromOdomRotation(pose_i, tilt_i);
  const Eigen::Matrix<T, 3, 3> rotation_ij =
      rotation_i.transpose() * OriginFromOdomRotation(pose_j, tilt_j);
  const Eigen::Matrix<T, 3, 1> delta(
      pose_j[0] - pose_i[0], pose_j[1] - pose_i[1], tilt_j[0] - tilt_i[0]);
  const Eigen::Matrix<T, 3, 1> translation_ij = rotation_i.transpose() * delta;
  T phi[3];
  ceres::RotationMatrixToAngleAxis(
      ceres::ColumnMajorAdapter3x3(rotation_ij.data()), phi);
  const Eigen::Matrix<T, 3, 1> in_plane(translation_ij[0] - measured[0],
                                        translation_ij[1] - measured[1],
                                        WrapAngle(phi[2] - measured[2]));
  Eigen::Map<Eigen::Matrix<T, 3, 1>> whitened(residual);
  whitened = sqrt_information.cast<T>() * in_plane;
  residual[3] = phi[0] / T(bounds.tilt_sigma_rad);
  residual[4] = phi[1] / T(bounds.tilt_sigma_rad);
  residual[5] = translation_ij[2] / T(bounds.height_sigma_m);
}

// A planar log's link between whole poses, its measurement fixed.
struct GroundOdometryLinkCost {
  GroundOdometryLinkCost(const PlanarPose& measured,
                         const Eigen::Matrix3d& sqrt_information,
                         const GroundBounds& bounds)
      : measured_(measured),
        sqrt_information_(sqrt_information),
        bounds_(bounds) {}

  template <typename T>
  bool operator()(const T* pose_i,
                  const T* tilt_i,
                  const T* pose_j,
                  const T* tilt_j,
                  T* residual) const {
    const T measured[3] = {
        T(measured_.x), T(measured_.y), T(measured_.yaw_rad)};
    GroundLinkResidual(pose_i,
                       tilt_i,
                       pose_j,
                       tilt_j,
                       measured,
                       sqrt_information_,
                       bounds_,
                       residual);
    return true;
  }

  PlanarPose measured_;
  Eigen::Matrix3d sqrt_information_;
  GroundBounds bounds_;
};

// The same, its measurement the logged odometry re-integrated with the
// systematics being refined (as SystematicOdometryLinkCost).
struct GroundSystematicOdometryLinkCost {
  GroundSystematicOdometryLinkCost(const OdometrySamples& samples,
                                   const Eigen::Matrix3d& sqrt_information,
                                   const GroundBounds& bounds,
                                   double wheel_track_m)
      : samples_(samples),
        sqrt_information_(sqrt_information),
        bounds_(bounds),
        wheel_track_m_(wheel_track_m) {}

  template <typename T>
  bool operator()(const T* pose_i,
                  const T* tilt_i,
                  const T* pose_j,
                  const T* tilt_j,
                  const T* intrinsics,
                  const T* offset_change_s,
                  T* residual) const {
    const PlanarMotion<T> motion = CorrectedOdometryMotion(
        samples_, intrinsics, offset_change_s[0], wheel_track_m_);
    const T measured[3] = {motion.x, motion.y, motion.yaw};
    GroundLinkResidual(pose_i,
                       tilt_i,
                       pose_j,
                       tilt_j,
                       measured,
                       sqrt_information_,
                       bounds_,
                       residual);
    return true;
  }

  OdometrySamples samples_;
  Eigen::Matrix3d sqrt_information_;
  GroundBounds bounds_;
  double wheel_track_m_;
};

// Lower-triangular W with W^T W = covariance^-1; false when the covariance
// is not positive definite.
bool SqrtInformation(const Eigen::Matrix3d& covariance, Eigen::Matrix3d* w);
bool SqrtInformation(const Eigen::Matrix<double, 6, 6>& covariance,
                     Eigen::Matrix<double, 6, 6>* w);

}  // namespace odomcal::internal
