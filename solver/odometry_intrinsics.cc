#include "odomcal/solver/odometry_intrinsics.h"

namespace odomcal {

double CorrectedYaw(const PlanarIncrement& increment,
                    const OdometryIntrinsics& intrinsics) {
  return CorrectedYaw(increment,
                      intrinsics.yaw_scale,
                      intrinsics.yaw_per_metre_rad,
                      intrinsics.yaw_rate_bias_rad_s);
}

double CorrectedForward(const PlanarIncrement& increment,
                        const OdometryIntrinsics& intrinsics) {
  const double track = intrinsics.wheel_track_m;
  return increment.forward_m + intrinsics.yaw_per_metre_rad * 0.25 * track *
                                   track / intrinsics.yaw_scale *
                                   increment.yaw_rad;
}

}  // namespace odomcal
