// Relative pose of two calibrated views from point correspondences, as in
// the simulations of Guo, Mirzaei & Roumeliotis (ICRA 2012), Section V: the
// 8-point algorithm followed by a two-view bundle adjustment, with the pose
// covariance of that bundle adjustment.
//
// Input: the same landmarks observed in views i and j, in normalised image
// coordinates u = (x/z, y/z) of each camera (pinhole, no distortion).
// Output: cam_i_from_cam_j = (R, t) with |t| = 1 (two views fix the
// translation only up to scale), i.e. a point p_in_cam_j maps to
// p_in_cam_i = R p_in_cam_j + t.
//
// Steps: (1) starting poses: cv::findFundamentalMat(FM_8POINT) on the
// normalised coordinates, which makes F the essential matrix E, and the
// decomposition cv::recoverPose picks (most points in front of both views);
// with `multi_start`, also the other decomposition of E that the cheirality
// test leaves viable (half of the points in front of both views) and the
// viable decompositions of OpenCV's 5-point solution (findEssentialMat,
// RANSAC) and of the best-ranked 7-point solutions of minimal samples
// (num_minimal_samples). (2) Linear triangulation of every point. (3) From each
// start, a Ceres bundle adjustment of the reprojection errors in pixels (f *
// (u_hat - u)) in both views over R (EigenQuaternionManifold), the unit t
// (SphereManifold<3>) and the points p_in_cam_i; no robust loss. The lowest
// cost wins.
//
// Why several starts: with 12 points, short baselines and up to 90 degrees
// of rotation, the bundle adjustment started at the 8-point solution alone
// stops in a local minimum in a few percent of the motions, with a
// translation direction tens of degrees off and a covariance that calls it
// accurate (docs/paper_reproduction.md, "Two-view estimates").
//
// Covariance: with H = J^T J of the bundle adjustment (J in pixels per
// tangent unit), the points are marginalised by the Schur complement
//   H_pose = H_pp - H_pl H_ll^-1 H_lp        (5x5: 3 rotation + 2 sphere)
// and Cov_tangent = sigma_px^2 H_pose^-1. It is reported in MotionPair's
// convention, order [rotation(3), translation(3)]: the rotation as a left
// perturbation R = Exp(phi) R_hat in radians (phi = 2 delta: Ceres' quaternion
// tangent delta is half the rotation vector), the translation in 3D through
// the sphere manifold's plus-Jacobian (3x2; rank 2: the unit length carries no
// uncertainty). Multiply the translation rows and columns by |t| when the
// translation is rescaled to a known length.
//
// Other minima (covariance_of_other_minima): at short baselines the data
// can fit two poses almost equally well (directions tens of degrees apart,
// costs within a few chi-square units); the first-order covariance at the
// best one then promises an accuracy the data do not have. Every other
// viable minimum k the starts reached, with likelihood ratio
// w_k = exp(-(cost_k - cost_best) / sigma_px^2) >= 1e-4, adds its spread:
//   C = C_best + sum_k w_k d_k d_k^T / (1 + sum_k w_k),
// d_k = [Log(R_k R_best^T), (I - t t^T) t_k], t the best unit translation
// (the rank-5 structure is kept). That is the covariance about the best pose
// of the mixture of the minima, each with C_best.
//
// Direction scan (direction_scan_points): the minima the starts reach are not
// all the data cannot rule out; at low parallax the cost is flat along a
// curved valley of directions. ScanTranslationDirection widens the
// covariance by the likelihood mass on a grid of directions
// (two_view_direction_scan.h).
#pragma once

#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace odomcal {

struct TwoViewOptions {
  double focal_length_px = 400.0;  // residuals are f * normalised error
  double pixel_sigma = 1.0;        // image noise, scales the covariance
  bool refine = true;              // false: 8-point + recoverPose only
  int max_num_iterations = 50;     // of the bundle adjustment
  // Bundle adjustments from every viable start (see the file comment);
  // false: from the 8-point solution only (the earlier estimator).
  bool multi_start = true;
  // With multi_start: also the 7-point solutions of this many minimal
  // samples (fixed, deterministic subsets of the points); their viable
  // decompositions are ranked by the Sampson error over all points and the
  // best num_minimal_sample_starts distinct ones become starts too. 0: none.
  int num_minimal_samples = 10;
  int num_minimal_sample_starts = 3;
  // With multi_start: the covariance also covers the other minima the data
  // cannot tell from the best one (see the file comment).
  bool covariance_of_other_minima = true;
  // With multi_start: the covariance also covers the directions on a grid of
  // this many over the hemisphere that fit the data almost as well
  // (two_view_direction_scan.h). 0: no scan.
  int direction_scan_points = 200;
  // When set, the bundle adjustment starts here (unit translation) instead
  // of at the 8-point solution (tests, multi-start).
  std::optional<Rigid3d> initial_cam_i_from_cam_j;
  void Check() const;  // throws std::invalid_argument naming the field
};

struct TwoViewEstimate {
  bool success = false;
  std::string failure;       // why not, when !success
  Rigid3d cam_i_from_cam_j;  // unit translation
  // See the file comment. Zero when !refine (no covariance without the
  // bundle adjustment) or when pixel_sigma is 0.
  MotionCovariance covariance = MotionCovariance::Zero();
  std::vector<Eigen::Vector3d> points_in_cam_i;  // triangulated / refined
  double initial_rms_px = 0.0;  // reprojection RMS after the 8-point step
  double final_rms_px = 0.0;    // after the bundle adjustment
  double final_cost = 0.0;      // Ceres cost, 1/2 sum of squared px
  int num_iterations = 0;       // of the winning bundle adjustment
  int num_starts = 0;           // bundle adjustments run
  int best_start = 0;           // index of the winner (0: the 8-point start)
  int num_other_minima = 0;     // in the covariance (see the file comment)
  // The covariance before the direction scan (the bundle adjustment's and
  // the other minima's): the core the scan adds its cells' spread to.
  MotionCovariance core_covariance = MotionCovariance::Zero();
  bool direction_scanned = false;  // two_view_direction_scan.h
  int num_direction_cells = 0;     // scan cells in the covariance
};

// Needs at least 8 correspondences (same order in both lists). Throws
// std::invalid_argument for mismatched sizes or invalid options; a
// degenerate configuration returns !success with the reason.
TwoViewEstimate EstimateTwoViewPose(
    const std::vector<Eigen::Vector2d>& normalized_in_cam_i,
    const std::vector<Eigen::Vector2d>& normalized_in_cam_j,
    const TwoViewOptions& options);

// The covariance of the file comment evaluated at a given pose (unit
// translation) and points (in cam i, at that scale) instead of at the
// estimate: e.g. at the truth, to tell a poorly linearised covariance from
// a wrong estimate. nullopt when the information is singular.
std::optional<MotionCovariance> TwoViewPoseCovarianceAt(
    const std::vector<Eigen::Vector2d>& normalized_in_cam_i,
    const std::vector<Eigen::Vector2d>& normalized_in_cam_j,
    const Rigid3d& cam_i_from_cam_j,
    const std::vector<Eigen::Vector3d>& points_in_cam_i,
    const TwoViewOptions& options);

}  // namespace odomcal
