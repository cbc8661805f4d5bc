// Joint refinement of the extrinsic, the metric scales, the clock offset and
// the odometry intrinsics (solver/odometry_intrinsics.h) over motion pairs that
// carry their logged odometry (MotionPair::odometry_samples, planar odometry)
// or, for 3-D odometry, its endpoint twists (MotionPair::odometry_twists:
// the clock offset only; the intrinsics are held).
//
// Each pair's odometry motion is re-integrated from its samples with the
// intrinsics, and moved to a slightly different clock offset through the
// endpoint twists: A(d) = Exp(-d xi_i) A Exp(d xi_j), first order in d, so the
// caller re-associates at the refined offset and refines again until d is
// negligible (adapters/systematics_estimation.h). The residual and its
// whitening are those of hand_eye_refine.h.
//
// Observability: a parameter the motion does not determine (singular
// information, or a standard deviation above its limit) is held at its start
// value and the reason is recorded; the rest are estimated again without it.
// E.g. a drive at constant curvature cannot tell yaw_scale, yaw_per_metre_rad
// and yaw_rate_bias_rad_s apart, and a drive without turns determines no
// clock offset from rotation.
#pragma once

#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/odometry_intrinsics.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>

#include <array>
#include <string>
#include <vector>

namespace odomcal {

struct SystematicsOptions {
  bool estimate_time_offset = true;
  bool estimate_intrinsics = true;
  // Above these standard deviations a parameter counts as undetermined by
  // the motion and is held.
  double max_time_offset_stddev_s = 0.005;
  double max_yaw_scale_stddev = 0.01;
  double max_yaw_per_metre_stddev_rad = 0.01;
  double max_yaw_rate_bias_stddev_rad_s = 0.002;
};

// Index of the systematic parameters: [offset, yaw_scale, yaw_per_metre,
// yaw_rate_bias].
constexpr int kNumSystematics = 4;
extern const std::array<const char*, kNumSystematics> kSystematicsNames;

struct SystematicsRefinement {
  bool usable = false;
  std::string report;  // Ceres BriefReport() of the last solve
  Rigid3d odom_from_cam;
  std::vector<double> metric_scales;  // NaN for segments without pairs
  // Change of the clock offset relative to the pairs' association (seconds,
  // odometry_time = camera_time + offset): add it and associate again.
  double time_offset_change_s = 0.0;
  OdometryIntrinsics intrinsics;
  // Per systematic parameter: estimated, its standard deviation (0 when
  // held) and, when held, why.
  std::array<bool, kNumSystematics> estimated{};
  std::array<double, kNumSystematics> stddev{};
  std::array<std::string, kNumSystematics> held_reason;
  // Covariance of [rx, ry, rz, tx, ty, s_k for each segment in
  // information_segments] marginalised over the estimated systematic
  // parameters (same units as RefinementResult::information); empty when the
  // information is singular.
  Eigen::MatrixXd extrinsic_covariance;
  // The same block with the systematic parameters held (the inverse of the
  // extrinsic's block of the information): extrinsic_covariance over it is
  // what estimating them adds.
  Eigen::MatrixXd extrinsic_conditional_covariance;
  std::vector<int> information_segments;
};

// Refines from `initial` / `initial_scales` (by segment) and
// `initial_intrinsics`, offset change 0, over pairs[indices]; every used pair
// must carry odometry_samples or odometry_twists (else usable is false).
// Translation z is held at initial's. The pairs are weighted by options.noise
// and their own covariances as given: with noise estimated from the data, pass
// both scaled (ScaleNoise, ScaleCovariances of noise_estimation.h).
SystematicsRefinement RefineSystematics(
    const MotionPairs& pairs,
    const std::vector<int>& indices,
    const Rigid3d& initial,
    const std::vector<double>& initial_scales,
    const OdometryIntrinsics& initial_intrinsics,
    const CalibrationOptions& options,
    const SystematicsOptions& systematics);

}  // namespace odomcal
