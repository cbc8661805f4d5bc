// Upper tail and critical values of the chi-square distribution: the one
// source of the gating thresholds (RANSAC, the final inlier test, the
// planarity check), so that every test with a false-alarm probability uses
// the same exact quantile. Eigen has none and Ceres exposes none.
#pragma once

namespace odomcal {

// P(X > x) for X ~ chi-square(dof); 1 for x <= 0. dof > 0.
double ChiSquareUpperTail(double x, double dof);

// The x with P(X > x) = probability, 0 < probability < 1; 0 for dof <= 0.
double ChiSquareCriticalValue(double probability, double dof);

// ChiSquareCriticalValue(0.001, dof): 99.9 % of chi-square(dof) lie below.
double ChiSquare999(double dof);

}  // namespace odomcal
