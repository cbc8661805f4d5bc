// Building odom_from_cam for a camera mounted on the robot from intuitive
// angles. Odometry frame: x forward, y left, z up. Camera: x right, y down,
// z forward (optical axis).
//
//   odom_from_cam = Rz(yaw) * Ry(pitch_down) * R_forward * Rz(roll)
//
// R_forward looks along odom +x with the image upright (cam z = odom x,
// cam x = -odom y, cam y = -odom z). yaw_deg turns the view to the left
// (90 = looking sideways to the left), pitch_down_deg tilts it towards the
// floor, roll_deg rotates the image about the optical axis (90 = camera
// rolled clockwise as seen from behind: image x points down in the world).
#pragma once

#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>

namespace odomcal {

Rigid3d MakeCameraMount(double yaw_deg,
                        double pitch_down_deg,
                        double roll_deg,
                        const Eigen::Vector3d& translation_m);

}  // namespace odomcal
