// Options of the odometer-camera calibration (see calibrate.h).
#pragma once

#include <cstdint>
#include <string>

namespace odomcal {

// Closed-form method of Guo, Mirzaei & Roumeliotis (ICRA 2012), Section IV.
enum class LinearMethod {
  kAlsp,  // step 2 uses the camera translations projected onto the motion plane
  kAls,   // step 2 uses the camera translations as measured
};

// How ALSP projects a camera translation onto the plane orthogonal to the
// third row r3 of R(q_yz) (Section IV-B).
//
// The orthogonal projection t - (r3.t) r3 (the paper's wording) only changes
// the third component of R(q_yz) t, and step 2 reads the first two: it gives
// exactly ALS (tested). The length-preserving projection rotates t into the
// plane instead, keeping its length: the variant that can differ. Measured
// over the paper's Monte Carlo protocol (docs/paper_reproduction.md) it is
// no better than ALS and slightly worse with landmark-based camera motions,
// so the paper's projection is the default.
enum class PlaneProjection {
  kOrthogonal,        // the paper's; identical to ALS
  kLengthPreserving,  // keeps |t|; measured slightly worse
};

enum class RobustLoss { kNone, kHuber, kCauchy };

// Default per-motion noise, used where a MotionPair carries no covariance.
// Standard deviations per relative motion (one keyframe pair).
struct NoiseModel {
  double odom_yaw_sigma_deg = 0.2;   // rotation about the odometry z axis
  double odom_yaw_sigma_rel = 0.01;  // + this fraction of |yaw|
  double odom_tilt_sigma_deg = 0.0;  // about x and y (0: planar log)
  double odom_translation_sigma_m = 0.002;   // per axis, constant part
  double odom_translation_sigma_rel = 0.01;  // + this fraction of the length
  double cam_rotation_sigma_deg = 0.05;      // per axis
  double cam_translation_sigma_rel = 0.01;   // per axis, fraction of length
  // Along the camera's direction of motion, fraction of the length; < 0: as
  // cam_translation_sigma_rel (isotropic). Not a flag: the noise estimation
  // (noise_estimation.h) sets it when the data separate the two (e.g. a
  // camera whose translation error is a direction error).
  double cam_translation_along_sigma_rel = -1.0;
  // The along-track standard deviation the covariance uses.
  double CamTranslationAlongSigmaRel() const {
    return cam_translation_along_sigma_rel < 0.0
               ? cam_translation_sigma_rel
               : cam_translation_along_sigma_rel;
  }
  void Check() const;  // throws like CalibrationOptions::Check
};

struct CalibrationOptions {
  LinearMethod method = LinearMethod::kAlsp;
  PlaneProjection alsp_projection = PlaneProjection::kOrthogonal;

  // Ceres batch refinement of eq. (24) after the closed form.
  bool refine = true;
  int max_num_iterations = 100;
  RobustLoss robust_loss = RobustLoss::kNone;
  double robust_loss_scale = 3.0;  // in standard deviations (whitened units)
  // Translation along the odometry z axis is unobservable under planar
  // motion; it is held at this value and reported as such.
  double fixed_translation_z_m = 0.0;
  // The held z is a prior, not a constant: fixed_translation_z_m with this
  // standard deviation (a plausible range of camera heights). Where SE(3)
  // odometry carries some information on z but does not determine it, the
  // refinement estimates z under this prior, and the covariance of the
  // rotation, x, y and the scales is the one with z free under it: a wrong
  // held z then no longer biases x and y beyond their stated uncertainty.
  // Planar odometry carries no information on z and does not depend on it.
  // 0: z is held exactly at fixed_translation_z_m.
  double translation_z_prior_sigma_m = 1.0;
  NoiseModel noise;

  // RANSAC over motion pairs around the closed form.
  bool use_ransac = true;
  double ransac_max_rotation_error_deg = 1.0;
  double ransac_max_translation_error_m = 0.02;
  double ransac_max_translation_error_rel = 0.05;  // + fraction of |t_odom|
  // Below this fraction of inliers the data are refused as inconsistent
  // (e.g. inverted poses fit a handful of pairs by chance).
  double ransac_min_inlier_ratio = 0.5;
  double ransac_confidence = 0.9999;
  int ransac_min_iterations = 50;
  int ransac_max_iterations = 5000;
  uint64_t ransac_seed = 0;

  // Excitation and refusal thresholds.
  double min_rotation_deg =
      2.0;  // a pair with |yaw| above this excites rotation
  int min_num_rotating_pairs = 2;
  int min_num_pairs = 2;
  // |angle(A_i)| and |angle(B_i)| agree for any extrinsic; a larger
  // difference means a wrong association or a bad camera motion.
  double max_angle_mismatch_deg = 2.0;
  // Largest standard deviations for which a quantity counts as determined.
  double max_rotation_stddev_deg = 2.0;
  double max_translation_stddev_m = 0.05;
  double max_scale_stddev_rel = 0.05;
  // Post-fit RMS translation residual over RMS odometry step length; above
  // it the poses contradict the model (e.g. cam_from_world given where
  // world_from_cam was expected).
  double max_relative_translation_residual = 0.2;

  // Noise levels estimated from the data (noise_estimation.h), starting from
  // `noise` and the pairs' own covariances; the covariance of the result and
  // the final inlier test (chi-square on the whitened residual) use them.
  // Off: the given noise is trusted and the pairs RANSAC chose are kept.
  bool estimate_noise = true;
  // Weight of the given noise in that estimation, in pseudo-observations per
  // estimated noise level: a scaled inverse chi-square prior centred on the
  // given noise, so that a short log or a component few pairs see stays near
  // it, while hundreds of pairs overrule it. 0 (the default): the data alone,
  // within the bounds of noise_estimation.h.
  double noise_prior_weight = 0.0;

  // Threads for the noise estimation's passes over the pairs; -1: the
  // hardware's. The result does not depend on it (fixed chunks of pairs,
  // added in order: solver/parallel_chunks.h).
  int num_threads = -1;

  // Throws std::invalid_argument whose message starts with the field's name
  // ("ransac_min_inlier_ratio must be in [0, 1], got 1.5"); the field names
  // of the noise model and of this struct are the CLI's flag names without
  // "--", so that odomcal can name the flag.
  void Check() const;
};

std::string ToString(LinearMethod method);
std::string ToString(PlaneProjection projection);
std::string ToString(RobustLoss loss);
// Inverse of ToString; throw std::invalid_argument on unknown names.
LinearMethod LinearMethodFromString(const std::string& name);
PlaneProjection PlaneProjectionFromString(const std::string& name);
RobustLoss RobustLossFromString(const std::string& name);

}  // namespace odomcal
