// A pose in the plane: the odometry frame in the odometry's origin frame
// under planar motion (x, y in metres, yaw about +z in radians).
#pragma once

#include "odomcal/solver/rigid3.h"

namespace odomcal {

struct PlanarPose {
  double x = 0.0, y = 0.0, yaw_rad = 0.0;
  Rigid3d ToRigid3d() const;  // rotation about +z, z = 0
};

// The planar part of a transform: x, y and the yaw about z (YawAboutZ).
PlanarPose PlanarFromRigid(const Rigid3d& transform);

}  // namespace odomcal
