// Monte Carlo data of the simulations of Guo, Mirzaei & Roumeliotis
// (ICRA 2012), Section V: motion pairs with a known extrinsic, noisy wheel
// odometry and noisy camera motions, each pair carrying the covariances of
// the noise actually applied (odom_covariance, cam_covariance), so that the
// batch refinement weighs them correctly.
//
// Robot motion i (odom_i_from_odom_j, planar): translation x, y ~ N(0, 0.2 m)
// each, z = 0; yaw ~ U[-pi/2, pi/2]. Extrinsic: RandomOdomFromCam()
// (motion_simulator.h). True camera motion: odom_from_cam^-1 * A *
// odom_from_cam, its translation divided by the segment's metric scale s_k
// (metres per reconstruction unit).
//
// Odometry noise (planar): yaw + N(0, odom_yaw_sigma_rad^2); translation x
// and y each + N(0, (odom_translation_sigma_rel * |t|)^2), |t| the motion's
// true length. Covariance diag(0, 0, sigma_yaw^2, sigma_t^2, sigma_t^2, 0)
// plus the floor below.
//
// Camera noise, one of:
//  * kParametric: rotation Exp(n) R, n ~ N(0, cam_rotation_sigma_rad^2 I3);
//    translation direction rotated by Exp(m), m ~ N(0, sigma_d^2) along the
//    two axes orthogonal to it (sigma_d = cam_direction_sigma_rad), its
//    length kept. Covariance diag(sigma_r^2 I3) and
//    |t|^2 sigma_d^2 (I - u u^T) for the translation.
//  * kLandmarks (the paper's): num_landmarks points drawn in front of camera
//    i (depth U[min_depth_m, max_depth_m], normalised image coordinates
//    U[-max_normalized_coordinate, +max_normalized_coordinate]) and kept only
//    when also at least min_depth_m in front of camera j ("visible" means
//    positive depth; there is no image boundary). Both projections get
//    N(0, (pixel_sigma / focal_length_px)^2) noise per coordinate; the
//    relative pose comes from EstimateTwoViewPose (two_view_pose.h: 8-point,
//    recoverPose, bundle adjustment) and its translation, a unit vector, is
//    scaled to the TRUE length in reconstruction units. This is the paper's
//    assumption of a consistent scale across the camera motions of a
//    segment (a monocular system's scale drifts; the paper does not model
//    that). The covariance is the bundle adjustment's with the points
//    marginalised, translation rows/columns scaled by that length.
//
// Floor: every covariance gets kCovarianceFloorRad^2 on its rotation
// diagonal and (kCovarianceFloorRel * max(|t|, 1e-3))^2 on its translation
// diagonal, which keeps planar odometry (no tilt noise), the unit-length
// direction of a camera translation and noise-free sweep points invertible
// without changing any realistic weight.
//
// Optional outliers: a fraction of pairs whose camera motion is replaced by
// a wrong one (extra rotation of 18-90 degrees, random direction of the same
// length); their covariances stay those of an inlier. Deterministic for a
// given std::mt19937_64 state.
#pragma once

#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/rigid3.h"

#include <random>
#include <string>
#include <vector>

namespace odomcal {

constexpr double kCovarianceFloorRad = 1e-6;
constexpr double kCovarianceFloorRel = 1e-6;

enum class CameraNoiseMode {
  kParametric,  // Gaussian rotation and translation-direction noise
  kLandmarks,   // the paper's: pixel noise, 8-point + bundle adjustment
};

std::string ToString(CameraNoiseMode mode);  // "parametric", "landmarks"
// Inverse of ToString; throws std::invalid_argument on unknown names.
CameraNoiseMode CameraNoiseModeFromString(const std::string& name);

struct PaperSimulationOptions {
  int num_motions = 20;
  int num_segments = 1;  // motions are split evenly, one scale each
  // Robot motion (paper: 0.2 m, U[-pi/2, pi/2]).
  double translation_sigma_m = 0.2;
  double max_abs_yaw_rad = 1.5707963267948966;
  // Metric scale of each segment, drawn log-uniformly from this range.
  double min_metric_scale = 0.5;
  double max_metric_scale = 2.0;

  // Odometry noise (paper: rotation SD 0-0.4 rad, translation SD
  // proportional to the motion's length).
  double odom_yaw_sigma_rad = 0.05;
  double odom_translation_sigma_rel = 0.05;

  CameraNoiseMode camera_noise = CameraNoiseMode::kLandmarks;
  // kParametric.
  double cam_rotation_sigma_rad = 0.005;
  double cam_direction_sigma_rad = 0.02;
  // kLandmarks (paper: 12 landmarks, f = 400 px, 0-2 px).
  int num_landmarks = 12;
  double focal_length_px = 400.0;
  double pixel_sigma = 1.0;
  double min_depth_m = 0.5;
  double max_depth_m = 5.0;
  double max_normalized_coordinate = 1.0;  // +-45 degrees field of view
  // Redraws of the landmarks when a two-view estimate fails; after that the
  // motion is dropped (counted in num_two_view_failures).
  int max_two_view_attempts = 3;
  // Two-view bundle adjustments from every viable start (two_view_pose.h);
  // false: from the 8-point solution only, as before the multi-start.
  bool two_view_multi_start = true;

  double outlier_fraction = 0.0;

  // Two-view estimator additions (two_view_pose.h), with
  // two_view_multi_start: minimal-sample starts, the covariance of the
  // other minima the data cannot tell apart and the direction scan
  // (two_view_direction_scan.h).
  int two_view_minimal_samples = 10;
  bool two_view_covariance_of_other_minima = true;
  int two_view_direction_scan_points = 200;  // 0: no direction scan

  void Check() const;  // throws std::invalid_argument naming the field
};

struct PaperSimulation {
  Rigid3d odom_from_cam;
  std::vector<double> metric_scales;  // per segment, metres per unit
  MotionPairs pairs;                  // measured, with covariances
  MotionPairs true_pairs;             // the same motions without noise
  std::vector<char> is_outlier;       // per pair
  // Per pair: the camera covariance before the two-view direction scan
  // (TwoViewEstimate::core_covariance, scaled and floored like
  // cam_covariance; equal to it without a scan).
  std::vector<MotionCovariance> cam_core_covariances;
  int num_two_view_failures = 0;  // motions dropped (kLandmarks)
};

// For a given extrinsic and scales (metric_scales.size() segments).
PaperSimulation SimulatePaperMotions(const PaperSimulationOptions& options,
                                     const Rigid3d& odom_from_cam,
                                     const std::vector<double>& metric_scales,
                                     std::mt19937_64* rng);

// Random extrinsic (RandomOdomFromCam) and random scales.
PaperSimulation SimulatePaperMotions(const PaperSimulationOptions& options,
                                     std::mt19937_64* rng);

}  // namespace odomcal
