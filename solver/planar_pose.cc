#include "odomcal/solver/planar_pose.h"

namespace odomcal {

Rigid3d PlanarPose::ToRigid3d() const {
  return Rigid3d(YawRotation(yaw_rad), Eigen::Vector3d(x, y, 0.0));
}

PlanarPose PlanarFromRigid(const Rigid3d& transform) {
  return {transform.translation.x(),
          transform.translation.y(),
          YawAboutZ(transform.rotation)};
}

}  // namespace odomcal
