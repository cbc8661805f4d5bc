// Alignment of an SfM reconstruction with the odometry origin frame, once
// the extrinsic and the metric scale are known: the similarity
// origin_from_sfm that maps reconstruction coordinates into metres in the
// odometry's fixed frame.
#pragma once

#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

namespace odomcal {

// x_in_b = scale * (rotation * x_in_a) + translation.
struct Sim3d {
  double scale = 1.0;
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Eigen::Vector3d operator*(const Eigen::Vector3d& x) const {
    return scale * (rotation * x) + translation;
  }
};

// Given, per image i, origin_from_cam_i (metres: odometry pose at the image
// time times odom_from_cam) and sfm_from_cam_i (reconstruction units), and
// the segment's metric scale s, finds R, t of origin_from_sfm = (s, R, t)
// minimising
//   sum_i |R_oc_i - R R_sc_i|_F^2 + w |p_o_i - (s R p_s_i + t)|^2,
// with w = position_weight_per_m2 (1 m of position error weighs like about
// one radian of orientation error). Both terms are linear in R, so one SVD
// of their joint cross-covariance solves it (orthogonal Procrustes).
// Requires at least one pose; returns identity rotation for none.
Sim3d AlignSfmToOrigin(const std::vector<Rigid3d>& origin_from_cam,
                       const std::vector<Rigid3d>& sfm_from_cam,
                       double metric_scale,
                       double position_weight_per_m2 = 1.0);

// cam_from_origin (metres) for a camera given as cam_from_sfm
// (reconstruction units).
Rigid3d CamFromOrigin(const Rigid3d& cam_from_sfm,
                      const Sim3d& origin_from_sfm);

}  // namespace odomcal
