// Composes the per-sample arcs in (x, y, unwrapped yaw) with the solver's
// PlanarExp/Compose, the functions the systematics refinement re-integrates
// the odometry with, so that both agree to rounding.
#include "odomcal/adapters/wheel_travel.h"

#include "odomcal/solver/angles.h"
#include "odomcal/solver/odometry_intrinsics.h"

#include <cmath>
#include <stdexcept>

namespace odomcal {

Trajectory IntegrateWheelTravels(const WheelTravels& travels, double track_m) {
  if (!(track_m > 0.0) || !std::isfinite(track_m)) {
    throw std::invalid_argument("wheel track must be > 0 and finite");
  }
  if (travels.samples.empty()) {
    throw std::invalid_argument("no wheel travel samples");
  }
  Trajectory trajectory;
  trajectory.planar = true;
  trajectory.source = travels.source;
  trajectory.poses.reserve(travels.samples.size());
  PlanarMotion<double> origin_from_odom{0.0, 0.0, 0.0};
  for (size_t k = 0; k < travels.samples.size(); ++k) {
    const WheelTravelSample& sample = travels.samples[k];
    if (k > 0) {
      const WheelTravelSample& previous = travels.samples[k - 1];
      const double left = sample.left_m - previous.left_m;
      const double right = sample.right_m - previous.right_m;
      origin_from_odom = Compose(
          origin_from_odom,
          PlanarExp(0.5 * (left + right), 0.0, (right - left) / track_m));
    }
    StampedPose pose;
    pose.stamp_ns = sample.stamp_ns;
    pose.world_from_sensor.rotation = YawRotation(origin_from_odom.yaw);
    pose.world_from_sensor.translation =
        Eigen::Vector3d(origin_from_odom.x, origin_from_odom.y, 0.0);
    trajectory.poses.push_back(pose);
  }
  return trajectory;
}

}  // namespace odomcal
