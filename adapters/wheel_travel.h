// Wheel travels of a differential drive and their dead reckoning into the
// planar odometry trajectory the rest of odomcal consumes.
//
// A wheel-travel log gives, per sample, the cumulative distance each wheel
// has rolled (metres, or encoder ticks over ticks per metre; decreasing when
// driving backwards). Between consecutive samples the wheels rolled dl and dr;
// with the nominal track b the robot moved
//   ds = (dl + dr) / 2 forward and turned dtheta = (dr - dl) / b,
// integrated as an arc of constant curvature (the SE(2) Exp of (ds, 0,
// dtheta)): exact when both wheel speeds are constant over the sample, and
// the same increments OdometryIncrements (odometry_increments.h) recovers, so
// the odometry intrinsics (yaw_scale, yaw_per_metre_rad, yaw_rate_bias_rad_s)
// then correct nominal radii and track exactly as for a logged pose odometry.
#pragma once

#include "odomcal/adapters/trajectory.h"

#include <cstdint>
#include <string>
#include <vector>

namespace odomcal {

struct WheelTravelSample {
  int64_t stamp_ns = 0;
  double left_m = 0.0;  // cumulative, from any origin
  double right_m = 0.0;
};

struct WheelTravels {
  // Strictly increasing stamp_ns.
  std::vector<WheelTravelSample> samples;
  std::string source;  // for messages
};

// What integrating a wheel-travel file needs from the user; 0: not given.
struct WheelTravelOptions {
  double track_m = 0.0;      // --wheel_track_m
  double ticks_per_m = 0.0;  // --wheel_ticks_per_m (tick columns only)
};

// origin_from_odom at every sample, the first at identity; planar, source
// copied. Throws std::invalid_argument when track_m is not > 0 or finite, or
// when there are no samples.
Trajectory IntegrateWheelTravels(const WheelTravels& travels, double track_m);

}  // namespace odomcal
