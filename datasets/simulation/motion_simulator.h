// Random odometer-camera motion pairs with a known extrinsic, following the
// simulation protocol of Guo, Mirzaei & Roumeliotis (ICRA 2012), Section V:
// robot translations N(0, 0.2 m) per axis in the plane, yaw increments
// U[-pi/2, pi/2], extrinsic translation U[-0.1, 0.1] m per axis and rotation
// angle U[-pi, pi] about an axis with N(0, 0.1) elements, normalised.
//
// Noise follows NoiseModel exactly as the solver models it: a measured
// rotation is Exp(n) * R_true with n ~ N(0, Sigma_rot), a measured
// translation is t_true + n_t, with standard deviations that grow with the
// motion's length. Deterministic for a given std::mt19937_64 state.
#pragma once

#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/rigid3.h"

#include <random>
#include <vector>

namespace odomcal {

struct MotionSimulatorOptions {
  int num_pairs = 50;
  int num_segments = 1;  // pairs are split evenly, each with its own scale
  double translation_sigma_m = 0.2;
  double min_yaw_rad = -1.5707963267948966;
  double max_yaw_rad = 1.5707963267948966;
  // Metric scale of each segment drawn log-uniformly from this range.
  double min_metric_scale = 0.2;
  double max_metric_scale = 5.0;
  // Noise; all-zero sigmas give exact data.
  bool add_noise = false;
  NoiseModel noise;
  // Fraction of pairs whose camera motion is replaced by a random one.
  double outlier_fraction = 0.0;
};

struct SimulatedMotions {
  Rigid3d odom_from_cam;
  std::vector<double> metric_scales;
  MotionPairs pairs;
  std::vector<char> is_outlier;  // per pair
};

// Random extrinsic per the paper's protocol.
Rigid3d RandomOdomFromCam(std::mt19937_64* rng);

// Exact camera motion for an odometry motion: odom_from_cam^-1 * A *
// odom_from_cam with its translation divided by metric_scale.
Rigid3d CameraMotionFromOdometryMotion(const Rigid3d& odom_i_from_odom_j,
                                       const Rigid3d& odom_from_cam,
                                       double metric_scale);

// Draws a noisy measurement of `motion` (rotation left-perturbed, translation
// additive) with the given per-axis sigmas; sigma entries may be zero.
Rigid3d PerturbMotion(const Rigid3d& motion,
                      const Eigen::Vector3d& rotation_sigma_rad,
                      const Eigen::Vector3d& translation_sigma,
                      std::mt19937_64* rng);

// Pairs for a given extrinsic and scales (scales.size() segments).
SimulatedMotions SimulateMotions(const MotionSimulatorOptions& options,
                                 const Rigid3d& odom_from_cam,
                                 const std::vector<double>& metric_scales,
                                 std::mt19937_64* rng);

// Pairs for a random extrinsic and random scales.
SimulatedMotions SimulateMotions(const MotionSimulatorOptions& options,
                                 std::mt19937_64* rng);

}  // namespace odomcal
