// The velocities (yaw rate, body-frame velocity) of the intervals before and
// after the one around the stamp bound how much the velocity changed inside
// it; at the ends of the log the interval's own velocity stands in.
#include "odomcal/adapters/odometry_interpolation_error.h"

#include "odomcal/adapters/association.h"
#include "odomcal/adapters/timestamp.h"
#include "odomcal/solver/angles.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace odomcal {
namespace {

// (x, y, yaw) of a planar pose.
Eigen::Vector3d PlanarState(const Rigid3d& pose) {
  const Eigen::Quaterniond q = WithPositiveScalar(pose.rotation.normalized());
  return Eigen::Vector3d(pose.translation.x(),
                         pose.translation.y(),
                         2.0 * std::atan2(q.z(), q.w()));
}

// Yaw rate and body-frame velocity of the constant-velocity motion between
// two samples; the velocity is the chord over the time, in the frame of the
// mean heading (the chord's direction on an arc), so that it is the same for
// every interval of a steady turn.
struct IntervalVelocity {
  double yaw_rate = 0.0;
  Eigen::Vector2d body_velocity = Eigen::Vector2d::Zero();
};

IntervalVelocity VelocityBetween(const StampedPose& from,
                                 const StampedPose& to) {
  const Eigen::Vector3d a = PlanarState(from.world_from_sensor);
  const Eigen::Vector3d b = PlanarState(to.world_from_sensor);
  const double seconds = ElapsedSeconds(from.stamp_ns, to.stamp_ns);
  const double turn = WrapAngle(b.z() - a.z());
  IntervalVelocity velocity;
  velocity.yaw_rate = turn / seconds;
  velocity.body_velocity =
      Eigen::Rotation2Dd(a.z() + 0.5 * turn).toRotationMatrix().transpose() *
      (b.head<2>() - a.head<2>()) / seconds;
  return velocity;
}

}  // namespace

Eigen::Matrix3d OdometryInterpolationCovariance(const Trajectory& odometry,
                                                int64_t stamp_ns) {
  const std::vector<StampedPose>& poses = odometry.poses;
  if (!odometry.planar || poses.size() < 2) return Eigen::Matrix3d::Zero();
  const auto after =
      std::upper_bound(poses.begin(),
                       poses.end(),
                       stamp_ns,
                       [](int64_t stamp, const StampedPose& pose) {
                         return stamp < pose.stamp_ns;
                       });
  if (after != poses.begin() && (after - 1)->stamp_ns == stamp_ns)
    return Eigen::Matrix3d::Zero();
  // Beyond an end: the end interval, continued (tau < 0 or > 1).
  const size_t b =
      after == poses.begin()
          ? 1
          : (after == poses.end() ? poses.size() - 1
                                  : static_cast<size_t>(after - poses.begin()));
  const size_t a = b - 1;

  const double interval_s =
      ElapsedSeconds(poses[a].stamp_ns, poses[b].stamp_ns);
  const double tau = static_cast<double>(stamp_ns - poses[a].stamp_ns) /
                     static_cast<double>(poses[b].stamp_ns - poses[a].stamp_ns);
  // Not a stamp InterpolateOdometry gives a pose for (1e-9: rounding).
  const double limit = kEndToleranceFraction + 1e-9;
  if (tau < -limit || tau > 1.0 + limit) return Eigen::Matrix3d::Zero();
  const IntervalVelocity current = VelocityBetween(poses[a], poses[b]);
  const IntervalVelocity before =
      a > 0 ? VelocityBetween(poses[a - 1], poses[a]) : current;
  const IntervalVelocity after_b =
      b + 1 < poses.size() ? VelocityBetween(poses[b], poses[b + 1]) : current;
  const double yaw_rate_change = std::abs(after_b.yaw_rate - before.yaw_rate);
  const double velocity_change =
      (after_b.body_velocity - before.body_velocity).norm();
  const double speed = current.body_velocity.norm();
  // A velocity that changes by dv at one instant inside the interval puts
  // the constant-velocity pose off by at most dv * interval * tau (1 - tau);
  // a yaw rate change also turns the path, by up to speed * d_omega *
  // interval over the interval. Beyond an end the pose is off by at most
  // dv * (time beyond) <= dv * interval * |tau (1 - tau)|, with dv the
  // change seen before the end (the one after it is unseen).
  const double weight = interval_s * std::abs(tau * (1.0 - tau));
  const double yaw_bound = yaw_rate_change * weight;
  const double position_bound =
      (velocity_change + speed * yaw_rate_change * interval_s) * weight;
  // Within +-bound, uniformly: standard deviation bound / sqrt(3).
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  covariance.diagonal() << yaw_bound * yaw_bound / 3.0,
      position_bound * position_bound / 3.0,
      position_bound * position_bound / 3.0;
  return covariance;
}

MotionCovariance RelativeMotionInterpolationCovariance(
    const Rigid3d& origin_from_odom_i,
    const Eigen::Matrix3d& covariance_i,
    const Rigid3d& origin_from_odom_j,
    const Eigen::Matrix3d& covariance_j) {
  // odom_i_from_odom_j: yaw_j - yaw_i and t = R_i^T (p_j - p_i), so
  //   d yaw = d yaw_j - d yaw_i,
  //   d t   = R_i^T (d p_j - d p_i) - d yaw_i * J t,  J = [[0, -1], [1, 0]].
  const double yaw_i = PlanarState(origin_from_odom_i).z();
  const Eigen::Matrix2d rotation_i_transposed =
      Eigen::Rotation2Dd(yaw_i).toRotationMatrix().transpose();
  const Eigen::Vector2d t =
      rotation_i_transposed *
      (origin_from_odom_j.translation - origin_from_odom_i.translation)
          .head<2>();
  // Rows: (yaw, t_x, t_y); columns: (d yaw, d x, d y) of one end.
  Eigen::Matrix3d jacobian_i = Eigen::Matrix3d::Zero();
  jacobian_i(0, 0) = -1.0;
  jacobian_i.block<2, 1>(1, 0) = -Eigen::Vector2d(-t.y(), t.x());
  jacobian_i.block<2, 2>(1, 1) = -rotation_i_transposed;
  Eigen::Matrix3d jacobian_j = Eigen::Matrix3d::Zero();
  jacobian_j(0, 0) = 1.0;
  jacobian_j.block<2, 2>(1, 1) = rotation_i_transposed;
  const Eigen::Matrix3d planar =
      jacobian_i * covariance_i * jacobian_i.transpose() +
      jacobian_j * covariance_j * jacobian_j.transpose();
  // Into MotionCovariance order: rotation z = 2, translation x, y = 3, 4.
  MotionCovariance covariance = MotionCovariance::Zero();
  const int index[3] = {2, 3, 4};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) covariance(index[r], index[c]) = planar(r, c);
  }
  return covariance;
}

}  // namespace odomcal
