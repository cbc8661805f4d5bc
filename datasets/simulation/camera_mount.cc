#include "odomcal/datasets/simulation/camera_mount.h"

#include "odomcal/solver/angles.h"

#include <cmath>

namespace odomcal {

Rigid3d MakeCameraMount(double yaw_deg,
                        double pitch_down_deg,
                        double roll_deg,
                        const Eigen::Vector3d& translation_m) {
  Eigen::Matrix3d forward;
  forward.col(0) = -Eigen::Vector3d::UnitY();
  forward.col(1) = -Eigen::Vector3d::UnitZ();
  forward.col(2) = Eigen::Vector3d::UnitX();
  const Eigen::Quaterniond rotation =
      Eigen::AngleAxisd(yaw_deg * kDegToRad, Eigen::Vector3d::UnitZ()) *
      Eigen::AngleAxisd(pitch_down_deg * kDegToRad, Eigen::Vector3d::UnitY()) *
      Eigen::Quaterniond(forward) *
      Eigen::AngleAxisd(roll_deg * kDegToRad, Eigen::Vector3d::UnitZ());
  return Rigid3d(WithPositiveScalar(rotation.normalized()), translation_m);
}

}  // namespace odomcal
