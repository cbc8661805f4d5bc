// Systematic errors of planar wheel odometry and their correction.
//
// A differential drive computes each sample's forward distance ds and heading
// change dtheta from nominal wheel radii and track. With true radii k_left,
// k_right times nominal and true track k_track times nominal b, and a gyro-like
// heading drift, the true heading change is
//   dtheta_true = yaw_scale * dtheta + yaw_per_metre_rad * ds
//                 + yaw_rate_bias_rad_s * dt
// with yaw_scale = ((k_left + k_right) / 2) / k_track and
// yaw_per_metre_rad = (k_right - k_left) / (k_track * b). The true distance is
// (k_left + k_right) / 2 * ds + (k_right - k_left) / 2 * (b / 2) * dtheta:
// its mean wheel factor a monocular camera cannot separate from the metric
// scale (held at 1: the extrinsic translation is in the odometry's metres);
// the second term, relative to the first, is
// forward_per_yaw_m = yaw_per_metre_rad * b^2 / (4 yaw_scale), known when the
// nominal track b is given (else 0: a turn then shifts the extrinsic y by
// about that much; it is nearly inseparable from y over short turns).
//
// The odometry between two times is the composition of its sample increments,
// each an SE(2) twist (forward, lateral, yaw) integrated over the sample
// period: exactly what the planar interpolation of adapters/association.h
// assumes. Re-integrating with corrected yaws gives the corrected motion.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <vector>

namespace odomcal {

struct OdometryIntrinsics {
  double yaw_scale = 1.0;
  double yaw_per_metre_rad = 0.0;
  double yaw_rate_bias_rad_s = 0.0;
  // Nominal wheel track b in metres, known (not estimated); 0: not given.
  double wheel_track_m = 0.0;
};

// One sample period (or the part of it between a pair's endpoints) of the
// odometry as logged: the SE(2) twist integrated over dt_s.
struct PlanarIncrement {
  double forward_m = 0.0;
  double lateral_m = 0.0;  // 0 for a non-holonomic drive
  double yaw_rad = 0.0;
  double dt_s = 0.0;
};

// The logged odometry between a pair's endpoints, and its body twist at each
// endpoint (per second: increment of the sample period holding the endpoint
// divided by its dt_s), for re-integrating it with other intrinsics and at a
// slightly shifted clock offset.
struct OdometrySamples {
  std::vector<PlanarIncrement> increments;
  PlanarIncrement twist_i;  // dt_s = 1
  PlanarIncrement twist_j;
};

// Planar pose or motion (x, y, yaw) for any scalar type (double or a Ceres
// Jet).
template <typename T>
struct PlanarMotion {
  T x, y, yaw;
};

// Corrected heading change of an increment.
template <typename T>
T CorrectedYaw(const PlanarIncrement& increment,
               const T& yaw_scale,
               const T& yaw_per_metre_rad,
               const T& yaw_rate_bias_rad_s) {
  return yaw_scale * increment.yaw_rad +
         yaw_per_metre_rad * increment.forward_m +
         yaw_rate_bias_rad_s * increment.dt_s;
}

// SE(2) Exp of the twist (vx, vy, theta): a = sin(theta)/theta and
// b = (1 - cos(theta))/theta use their series below 1e-4 (error ~theta^4).
template <typename T>
PlanarMotion<T> PlanarExp(const T& vx, const T& vy, const T& theta) {
  using std::abs;
  using std::cos;
  using std::sin;
  T a, b;
  if (abs(theta) < 1e-4) {
    a = T(1.0) - theta * theta / 6.0;
    b = theta * (T(0.5) - theta * theta / 24.0);
  } else {
    a = sin(theta) / theta;
    b = (T(1.0) - cos(theta)) / theta;
  }
  return {a * vx - b * vy, b * vx + a * vy, theta};
}

// left * right.
template <typename T>
PlanarMotion<T> Compose(const PlanarMotion<T>& left,
                        const PlanarMotion<T>& right) {
  using std::cos;
  using std::sin;
  const T c = cos(left.yaw), s = sin(left.yaw);
  return {left.x + c * right.x - s * right.y,
          left.y + s * right.x + c * right.y,
          left.yaw + right.yaw};
}

// The odometry motion from endpoint i to endpoint j with the given
// intrinsics, both endpoints shifted later in time by offset_change_s
// (first order in the shift, through the endpoint twists):
//   Exp(-d xi_i) * T_ij * Exp(d xi_j).
// parameters = [yaw_scale, yaw_per_metre_rad, yaw_rate_bias_rad_s];
// wheel_track_m: the nominal track (0: not given, no forward correction).
template <typename T>
PlanarMotion<T> CorrectedOdometryMotion(const OdometrySamples& samples,
                                        const T* intrinsics,
                                        const T& offset_change_s,
                                        double wheel_track_m) {
  const T forward_per_yaw_m =
      intrinsics[1] * (0.25 * wheel_track_m * wheel_track_m) / intrinsics[0];
  PlanarMotion<T> motion{T(0.0), T(0.0), T(0.0)};
  for (const PlanarIncrement& increment : samples.increments) {
    motion = Compose(
        motion,
        PlanarExp(increment.forward_m + forward_per_yaw_m * increment.yaw_rad,
                  T(increment.lateral_m),
                  CorrectedYaw(
                      increment, intrinsics[0], intrinsics[1], intrinsics[2])));
  }
  const auto shift = [&](const PlanarIncrement& twist, const T& d) {
    return PlanarExp(
        d * (twist.forward_m + forward_per_yaw_m * twist.yaw_rad),
        d * twist.lateral_m,
        d * CorrectedYaw(twist, intrinsics[0], intrinsics[1], intrinsics[2]));
  };
  return Compose(Compose(shift(samples.twist_i, -offset_change_s), motion),
                 shift(samples.twist_j, offset_change_s));
}

// Heading change of the corrected odometry (intrinsics as doubles).
double CorrectedYaw(const PlanarIncrement& increment,
                    const OdometryIntrinsics& intrinsics);
// Forward distance of the corrected odometry (see forward_per_yaw_m above).
double CorrectedForward(const PlanarIncrement& increment,
                        const OdometryIntrinsics& intrinsics);

}  // namespace odomcal
