#include "odomcal/solver/similarity_alignment.h"

#include <Eigen/SVD>

namespace odomcal {

Sim3d AlignSfmToOrigin(const std::vector<Rigid3d>& origin_from_cam,
                       const std::vector<Rigid3d>& sfm_from_cam,
                       double metric_scale,
                       double position_weight_per_m2) {
  Sim3d result;
  result.scale = metric_scale;
  const size_t n = std::min(origin_from_cam.size(), sfm_from_cam.size());
  if (n == 0) return result;
  Eigen::Vector3d mean_origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d mean_sfm = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    mean_origin += origin_from_cam[i].translation;
    mean_sfm += sfm_from_cam[i].translation;
  }
  mean_origin /= static_cast<double>(n);
  mean_sfm /= static_cast<double>(n);
  // Cross-covariance whose projection onto SO(3) maximises
  // sum trace(R^T (R_oc R_sc^T)) + w sum (dp_o)^T R (s dp_s).
  Eigen::Matrix3d cross = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    cross += origin_from_cam[i].rotation.toRotationMatrix() *
             sfm_from_cam[i].rotation.toRotationMatrix().transpose();
    cross +=
        position_weight_per_m2 *
        (origin_from_cam[i].translation - mean_origin) *
        (metric_scale * (sfm_from_cam[i].translation - mean_sfm)).transpose();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(
      cross, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d correction = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0) {
    correction(2, 2) = -1.0;
  }
  const Eigen::Matrix3d rotation =
      svd.matrixU() * correction * svd.matrixV().transpose();
  result.rotation = Eigen::Quaterniond(rotation).normalized();
  result.translation = mean_origin - metric_scale * (rotation * mean_sfm);
  return result;
}

Rigid3d CamFromOrigin(const Rigid3d& cam_from_sfm,
                      const Sim3d& origin_from_sfm) {
  // x_sfm = R^T (x_o - t) / s, x_cam[m] = s (R_cs x_sfm + t_cs)
  //       = R_cs R^T x_o - R_cs R^T t + s t_cs.
  const Eigen::Quaterniond rotation =
      (cam_from_sfm.rotation * origin_from_sfm.rotation.conjugate())
          .normalized();
  return Rigid3d(rotation,
                 origin_from_sfm.scale * cam_from_sfm.translation -
                     rotation * origin_from_sfm.translation);
}

}  // namespace odomcal
