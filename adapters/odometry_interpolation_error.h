// How wrong the interpolated odometry pose at a camera time may be.
//
// InterpolateOdometry (association.h) assumes constant linear and angular
// velocity between the two samples around a stamp. With low-rate odometry
// (a few Hz) a robot that starts or stops turning in between breaks that
// assumption: the pose is off by up to a few centimetres and degrees. The
// error is bounded from the change of velocity across the interval, seen by
// the intervals before and after it: a yaw rate that changes by d_omega at
// one instant inside an interval of length T puts the interpolated yaw off by
// at most d_omega * T * tau (1 - tau) at the fraction tau of the interval
// (the worst case: the change at the stamp itself); the position likewise
// from the change of the body-frame velocity, plus the turn of the path,
// speed * d_omega * T * T tau (1 - tau). The error is taken as uniform within
// +-bound (standard deviation bound / sqrt(3)), yaw and position separately
// (position isotropic in the plane), and enters the motion pair's odometry
// covariance. At constant velocity, including steady turns, it is zero.
#pragma once

#include "odomcal/adapters/trajectory.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>

#include <cstdint>

namespace odomcal {

// Covariance of the interpolation error of origin_from_odom at stamp_ns, in
// the order (yaw in radians, x, y in the origin frame in metres). Within
// InterpolateOdometry's end tolerance beyond the first or last sample, the
// bound of the end interval continued, from the velocity change seen before
// that end. Zero at a sample's own stamp, further outside the log, and for
// non-planar logs (slerp + linear interpolation; their error is not
// estimated). Precondition: strictly increasing stamps.
Eigen::Matrix3d OdometryInterpolationCovariance(const Trajectory& odometry,
                                                int64_t stamp_ns);

// Covariance of odom_i_from_odom_j = Inverse(origin_from_odom_i) *
// origin_from_odom_j (MotionCovariance order and conventions) given the
// interpolation covariances of its two ends, taken as independent (errors of
// the same sign at both ends, e.g. in one sample interval, cancel in the
// relative motion: independence overstates them, never understates).
MotionCovariance RelativeMotionInterpolationCovariance(
    const Rigid3d& origin_from_odom_i,
    const Eigen::Matrix3d& covariance_i,
    const Rigid3d& origin_from_odom_j,
    const Eigen::Matrix3d& covariance_j);

}  // namespace odomcal
