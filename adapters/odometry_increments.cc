// Increments by the SE(2) Log of consecutive samples; re-integration by the
// SE(2) Exp (solver/odometry_intrinsics.h), so that the two are inverse.
#include "odomcal/adapters/odometry_increments.h"

#include "odomcal/adapters/timestamp.h"

#include <algorithm>
#include <cmath>

namespace odomcal {
namespace {

PlanarIncrement Scaled(const PlanarIncrement& increment, double factor) {
  return {factor * increment.forward_m,
          factor * increment.lateral_m,
          factor * increment.yaw_rad,
          factor * increment.dt_s};
}

// Index k of the sample period [t_k, t_k+1] holding the stamp (clamped).
size_t PeriodOf(const Trajectory& odometry, int64_t stamp_ns) {
  const auto after =
      std::upper_bound(odometry.poses.begin(),
                       odometry.poses.end(),
                       stamp_ns,
                       [](int64_t stamp, const StampedPose& pose) {
                         return stamp < pose.stamp_ns;
                       });
  const size_t k =
      after == odometry.poses.begin()
          ? 0
          : static_cast<size_t>(after - odometry.poses.begin()) - 1;
  return std::min(k, odometry.poses.size() - 2);
}

}  // namespace

std::vector<PlanarIncrement> OdometryIncrements(const Trajectory& odometry) {
  std::vector<PlanarIncrement> increments;
  for (size_t k = 0; k + 1 < odometry.poses.size(); ++k) {
    const Rigid3d a_from_b = Inverse(odometry.poses[k].world_from_sensor) *
                             odometry.poses[k + 1].world_from_sensor;
    const double theta = YawAboutZ(a_from_b.rotation);
    // V(theta)^-1 p with V = [[a, -b], [b, a]] (see PlanarExp).
    double a = 1.0 - theta * theta / 6.0, b = 0.5 * theta;
    if (std::abs(theta) >= 1e-4) {
      a = std::sin(theta) / theta;
      b = (1.0 - std::cos(theta)) / theta;
    }
    const Eigen::Vector2d p = a_from_b.translation.head<2>();
    const double inverse_det = 1.0 / (a * a + b * b);
    increments.push_back({inverse_det * (a * p.x() + b * p.y()),
                          inverse_det * (-b * p.x() + a * p.y()),
                          theta,
                          ElapsedSeconds(odometry.poses[k].stamp_ns,
                                         odometry.poses[k + 1].stamp_ns)});
  }
  return increments;
}

Trajectory CorrectOdometry(const Trajectory& odometry,
                           const OdometryIntrinsics& intrinsics) {
  Trajectory corrected = odometry;
  if (odometry.poses.empty()) return corrected;
  const std::vector<PlanarIncrement> increments = OdometryIncrements(odometry);
  const Rigid3d& first = odometry.poses.front().world_from_sensor;
  PlanarMotion<double> pose{
      first.translation.x(), first.translation.y(), YawAboutZ(first.rotation)};
  for (size_t k = 0; k < increments.size(); ++k) {
    const PlanarIncrement& increment = increments[k];
    pose = Compose(pose,
                   PlanarExp(CorrectedForward(increment, intrinsics),
                             increment.lateral_m,
                             CorrectedYaw(increment, intrinsics)));
    Rigid3d& out = corrected.poses[k + 1].world_from_sensor;
    out = Rigid3d(YawRotation(pose.yaw),
                  Eigen::Vector3d(pose.x, pose.y, out.translation.z()));
  }
  return corrected;
}

void AttachOdometrySamples(const Trajectory& odometry, MotionPairs* pairs) {
  if (odometry.poses.size() < 2) return;
  const std::vector<PlanarIncrement> increments = OdometryIncrements(odometry);
  const auto per_second = [&](size_t k) {
    PlanarIncrement twist = Scaled(increments[k], 1.0 / increments[k].dt_s);
    twist.dt_s = 1.0;
    return twist;
  };
  for (MotionPair& pair : *pairs) {
    OdometrySamples samples;
    const size_t first = PeriodOf(odometry, pair.stamp_i_ns);
    const size_t last = PeriodOf(odometry, pair.stamp_j_ns);
    for (size_t k = first; k <= last; ++k) {
      // The endpoints' own periods are cut at the stamps, not at the
      // samples: a stamp within InterpolateOdometry's end tolerance lies
      // beyond the first or last sample, and its period is continued there
      // (fraction above 1), as the association interpolates it.
      const int64_t from =
          k == first ? pair.stamp_i_ns : odometry.poses[k].stamp_ns;
      const int64_t to =
          k == last ? pair.stamp_j_ns : odometry.poses[k + 1].stamp_ns;
      if (to <= from) continue;
      const double fraction =
          static_cast<double>(to - from) /
          static_cast<double>(odometry.poses[k + 1].stamp_ns -
                              odometry.poses[k].stamp_ns);
      samples.increments.push_back(Scaled(increments[k], fraction));
    }
    samples.twist_i = per_second(first);
    samples.twist_j = per_second(last);
    pair.odometry_samples = std::move(samples);
  }
}

void AttachOdometryTwists(const Trajectory& odometry, MotionPairs* pairs) {
  if (odometry.poses.size() < 2) return;
  const auto twist_at = [&](int64_t stamp_ns) {
    const size_t k = PeriodOf(odometry, stamp_ns);
    const StampedPose& a = odometry.poses[k];
    const StampedPose& b = odometry.poses[k + 1];
    const double dt_s = ElapsedSeconds(a.stamp_ns, b.stamp_ns);
    const Eigen::Quaterniond& r_a = a.world_from_sensor.rotation;
    const Eigen::Vector3d phi =
        LogRotation(r_a.conjugate() * b.world_from_sensor.rotation);
    const double tau = ElapsedSeconds(a.stamp_ns, stamp_ns) / dt_s;
    const Eigen::Quaterniond r_at = r_a * ExpRotation(tau * phi);
    Eigen::Matrix<double, 6, 1> twist;
    twist.head<3>() = phi / dt_s;
    twist.tail<3>() =
        r_at.conjugate() *
        (b.world_from_sensor.translation - a.world_from_sensor.translation) /
        dt_s;
    return twist;
  };
  for (MotionPair& pair : *pairs) {
    pair.odometry_twists = OdometryEndpointTwists{twist_at(pair.stamp_i_ns),
                                                  twist_at(pair.stamp_j_ns)};
  }
}

}  // namespace odomcal
