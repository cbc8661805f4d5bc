// Angle constants and wrapping, shared by every folder (one definition of pi
// instead of a local copy per file).
#pragma once

#include <cmath>

namespace odomcal {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;
constexpr double kRadToDeg = 180.0 / kPi;

// The angle in [-pi, pi] (std::remainder by 2 pi).
inline double WrapAngle(double angle_rad) {
  return std::remainder(angle_rad, 2.0 * kPi);
}

}  // namespace odomcal
