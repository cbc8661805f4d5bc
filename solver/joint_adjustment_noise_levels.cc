// The joint adjustment's noise levels from its residuals: the pixel sigma
// and the odometry's variance factor (joint_adjustment_internal.h).
#include "odomcal/solver/joint_adjustment_cost.h"
#include "odomcal/solver/joint_adjustment_internal.h"

#include <algorithm>
#include <cmath>

namespace odomcal::internal {

JointProblem::PixelStatistics JointProblem::UpdatePixelSigma(
    double max_sigmas, bool mark_outliers) {
  std::vector<double> norms(input_.observations.size(), -1.0);
  std::vector<double> used_norms;
  for (size_t k = 0; k < input_.observations.size(); ++k) {
    if (!used_[k] || !determined_[input_.observations[k].point]) continue;
    Eigen::Vector2d residual;
    if (!ReprojectionResidual(k, &residual)) continue;
    norms[k] = residual.norm();
    used_norms.push_back(norms[k]);
  }
  PixelStatistics statistics;
  if (used_norms.empty()) return statistics;
  std::nth_element(used_norms.begin(),
                   used_norms.begin() + used_norms.size() / 2,
                   used_norms.end());
  // The median of a 2D Gaussian residual's norm is sigma sqrt(2 ln 2).
  const double robust_sigma =
      used_norms[used_norms.size() / 2] / std::sqrt(2.0 * std::log(2.0));
  const double threshold = max_sigmas * robust_sigma;
  double sum_squares = 0.0;
  std::vector<char> point_seen(input_.points.size(), 0);
  int num_points = 0;
  for (size_t k = 0; k < norms.size(); ++k) {
    if (!used_[k] || !determined_[input_.observations[k].point]) continue;
    if (norms[k] < 0.0 || norms[k] > threshold) {
      if (mark_outliers) {
        used_[k] = 0;
        ++statistics.num_marked;
      }
      continue;
    }
    sum_squares += norms[k] * norms[k];
    ++statistics.num_inliers;
    const int point = input_.observations[k].point;
    if (!point_seen[point]) {
      point_seen[point] = 1;
      ++num_points;
    }
  }
  if (statistics.num_inliers == 0) return statistics;
  statistics.rms = std::sqrt(sum_squares / (2.0 * statistics.num_inliers));
  // Each point takes 3 of its observations' degrees of freedom, each free
  // pose 3 (6 when tilted; the odometry's share of the poses is small
  // beside the images'), each mount 5.
  int num_free_poses = 0;
  for (const char held : held_) num_free_poses += held ? 0 : 1;
  const double pose_dof = tilted_ ? 6.0 : 3.0;
  const double dof = 2.0 * statistics.num_inliers - 3.0 * num_points -
                     pose_dof * num_free_poses -
                     5.0 * static_cast<double>(mounts_.size());
  statistics.sigma = dof > 0.0 ? std::sqrt(sum_squares / dof) : statistics.rms;
  return statistics;
}

double JointProblem::EstimateOdometryFactor() {
  const double per_link = MeasuredLinkDof();
  const double dof = per_link * static_cast<double>(input_.links.size()) - 3.0;
  constexpr double kMinDof = 30.0;
  if (dof < kMinDof) return odometry_factor_;
  const double rms = OdometryRms();
  const double sum =
      rms * rms * per_link * static_cast<double>(input_.links.size());
  odometry_factor_ =
      std::clamp(sum / dof, kMinOdometryFactor, kMaxOdometryFactor);
  return odometry_factor_;
}

void JointProblem::PlanarLinkResidual(const OdometryLink& link,
                                      const Eigen::Matrix3d& w,
                                      double* residual) const {
  const double length =
      std::hypot(link.odom_i_from_odom_j.x, link.odom_i_from_odom_j.y);
  const GroundBounds bounds = GroundBoundsOf(ground_rate_, length);
  if (input_.systematics) {
    const double wheel_track = input_.systematics->intrinsics.wheel_track_m;
    if (on_ground_) {
      GroundSystematicOdometryLinkCost(*link.samples, w, bounds, wheel_track)(
          poses_[link.image_i].data(),
          tilts_[link.image_i].data(),
          poses_[link.image_j].data(),
          tilts_[link.image_j].data(),
          intrinsics_,
          &offset_change_s_,
          residual);
    } else {
      SystematicOdometryLinkCost(*link.samples, w, wheel_track)(
          poses_[link.image_i].data(),
          poses_[link.image_j].data(),
          intrinsics_,
          &offset_change_s_,
          residual);
    }
  } else if (on_ground_) {
    GroundOdometryLinkCost(link.odom_i_from_odom_j, w, bounds)(
        poses_[link.image_i].data(),
        tilts_[link.image_i].data(),
        poses_[link.image_j].data(),
        tilts_[link.image_j].data(),
        residual);
  } else {
    OdometryLinkCost(link.odom_i_from_odom_j, w)(
        poses_[link.image_i].data(), poses_[link.image_j].data(), residual);
  }
}

double JointProblem::EstimateGroundRate() {
  if (!on_ground_ || input_.links.empty()) return ground_rate_;
  double sum = 0.0;
  for (const OdometryLink& link : input_.links) {
    Eigen::Matrix3d w;
    SqrtInformation(link.covariance, &w);
    double residual[6];
    PlanarLinkResidual(link, w, residual);
    sum += residual[3] * residual[3] + residual[4] * residual[4] +
           residual[5] * residual[5];
  }
  // The bounds grow with the rate (but for their floors): one factor on
  // its variance.
  const double factor = sum / (3.0 * static_cast<double>(input_.links.size()));
  ground_rate_ = std::clamp(
      ground_rate_ * std::sqrt(factor), kMinGroundRate, kMaxGroundRate);
  return ground_rate_;
}

double JointProblem::OdometryRms() const {
  double sum = 0.0;
  for (const OdometryLink& link : input_.links) {
    if (se3_) {
      Eigen::Matrix<double, 6, 6> w6;
      SqrtInformation(link.motion_3d->covariance, &w6);
      const Se3OdometryLinkCost cost(link.motion_3d->odom_i_from_odom_j, w6);
      Eigen::Matrix<double, 6, 1> residual;
      cost(poses_[link.image_i].data(),
           tilts_[link.image_i].data(),
           poses_[link.image_j].data(),
           tilts_[link.image_j].data(),
           residual.data());
      sum += residual.squaredNorm();
      continue;
    }
    Eigen::Matrix3d w;
    SqrtInformation(link.covariance, &w);
    double residual[6];
    PlanarLinkResidual(link, w, residual);
    sum += residual[0] * residual[0] + residual[1] * residual[1] +
           residual[2] * residual[2];
  }
  const double per_link = MeasuredLinkDof();
  return std::sqrt(sum / (per_link * static_cast<double>(input_.links.size())));
}

}  // namespace odomcal::internal
