// The two-view covariance widened by a scan of the translation direction.
//
// At low parallax the two-view cost is far from quadratic in the translation
// direction: the rotation and the direction trade off along a curved valley
// (the bas-relief ambiguity), so the first-order covariance at the minimum
// can call a direction accurate to 2 degrees when directions 20 degrees
// away fit the data only a few chi-square units worse. Most of the motions
// whose error lies far outside their covariance are of this kind
// (docs/paper_reproduction.md, "Two-view estimates").
//
// The scan integrates the likelihood over the direction instead: on a
// Fibonacci grid of `num_points` directions over the hemisphere of the
// estimate's direction t_hat, each direction t_k outside the covariance's
// own 3-sigma core gets the rotation R_k that minimises the Sampson error
// (the reprojection cost with the points eliminated, to first order) with t_k
// held; with Delta_k = 2 (S_k - S_hat) / sigma_px^2 its cell, of area
// 2 pi / num_points, carries the likelihood mass
//   w_k = exp(-Delta_k / 2) (2 pi / num_points) / (2 pi sigma_1 sigma_2)
// relative to the core's Gaussian (sigma_1, sigma_2: the covariance's
// direction standard deviations). The covariance about the estimate of
// that mixture is
//   C = C_hat + sum_k w_k d_k d_k^T / (1 + sum_k w_k),
// d_k = [Log(R_k R_hat^T), (I - t_hat t_hat^T) t_k], the form of the other
// minima's spread (two_view_pose.h). A grid resolves only spreads wider than
// its spacing sqrt(2 pi / num_points): where sigma_1 is below
// kDirectionScanMinSpreadOfSpacing times the spacing, the cost is quadratic
// over many cells and the scan is skipped (its cells' masses would be wrong).
#pragma once

#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>

#include <vector>

namespace odomcal {

// The scan runs where the direction's largest standard deviation is at least
// this fraction of the grid spacing.
constexpr double kDirectionScanMinSpreadOfSpacing = 0.5;

struct DirectionScan {
  MotionCovariance covariance = MotionCovariance::Zero();  // widened
  bool scanned = false;    // false: the covariance is returned unchanged
  int num_cells_used = 0;  // grid cells whose mass entered the covariance
};

// `covariance` of `cam_i_from_cam_j` (unit translation) in MotionPair's
// layout (two_view_pose.h), for the correspondences in normalised
// coordinates; residuals are focal_length_px times normalised errors, the
// noise pixel_sigma. num_points <= 0 or pixel_sigma <= 0: no scan.
DirectionScan ScanTranslationDirection(
    const std::vector<Eigen::Vector2d>& normalized_in_cam_i,
    const std::vector<Eigen::Vector2d>& normalized_in_cam_j,
    const Rigid3d& cam_i_from_cam_j,
    const MotionCovariance& covariance,
    double focal_length_px,
    double pixel_sigma,
    int num_points);

}  // namespace odomcal
