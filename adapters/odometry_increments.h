// Planar wheel odometry as sample increments (solver/odometry_intrinsics.h):
// what a pair's odometry motion is re-integrated from when the clock offset
// and the odometry intrinsics are estimated, and the corrected odometry the
// metric export uses; for 3-D odometry, the endpoint twists that move a
// pair's motion to another clock offset.
#pragma once

#include "odomcal/adapters/trajectory.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/odometry_intrinsics.h"

#include <vector>

namespace odomcal {

// One increment per pair of consecutive samples: the SE(2) Log of
// Inverse(origin_from_odom_k) * origin_from_odom_k+1 (forward, lateral, yaw)
// and its duration. Planar odometry only (roll, pitch and z are ignored).
std::vector<PlanarIncrement> OdometryIncrements(const Trajectory& odometry);

// The odometry re-integrated with corrected yaws from its first pose; same
// stamps. Identity intrinsics give back the input (to rounding).
Trajectory CorrectOdometry(const Trajectory& odometry,
                           const OdometryIntrinsics& intrinsics);

// Sets every pair's odometry_samples from the logged odometry between its
// stamps (odometry times, inside the log or within InterpolateOdometry's end
// tolerance beyond it): the increments, the first and last cut at the stamps
// (a fraction tau of a sample's twist, exact for the planar interpolation of
// association.h, and continued beyond an end as it continues), and the twist
// per second of the sample period holding each endpoint. Needs planar
// odometry with >= 2 samples.
void AttachOdometrySamples(const Trajectory& odometry, MotionPairs* pairs);

// Sets every pair's odometry_twists from 3-D odometry (>= 2 samples): at
// each stamp, the velocity of InterpolateOdometry's interpolation of the
// sample period holding it (slerp: the rotation vector of the period over
// its duration; linear: the translation over its duration, turned into the
// odometry frame at the stamp), so that origin_from_odom(t + h) =
// origin_from_odom(t) Exp(h xi) to first order in h.
void AttachOdometryTwists(const Trajectory& odometry, MotionPairs* pairs);

}  // namespace odomcal
