#include "odomcal/solver/odometry_intrinsics.h"

namespace odomcal {

double CorrectedYaw(const PlanarIncrement& increment,
                    const OdometryIntrinsics& intrinsics) {
  return CorrectedYaw(increment,
                      intrinsics.yaw_scale,
                      intrinsics.yaw_per_metre_rad,
                      intrinsics.yaw_rate_bias_rad_s);
}

}  // namespace odomcal
