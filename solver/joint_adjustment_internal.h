// The joint adjustment's problem (internal: not installed; Ceres types stay
// out of the public headers). The model: joint_adjustment.h. Ceres problem:
// per image a pose block (3: x, y, yaw) and with RobotMotionModel::kSE3 a
// tilt block (3: z, roll, pitch), per mount the extrinsic as [q (4,
// EigenQuaternionManifold), t_xy (2), t_z (1, constant)], per point a block
// (3), per camera an intrinsics block (held unless refined). Solved with the
// sparse Schur complement (points eliminated first), two or three times:
// each pass estimates the pixel sigma from its residuals and leaves out the
// observations beyond max_reprojection_sigmas for the next (AdjustJointly,
// joint_adjustment.cc).
//
// JointProblem's parts, one concept per file:
//   - joint_adjustment_problem.cc: the parameters, the gauge, the Ceres
//     problem and its solve, the result;
//   - joint_adjustment_noise_levels.cc: the pixel sigma and the odometry's
//     level from the residuals;
//   - joint_adjustment_extrinsic_covariance.cc: the extrinsic's covariance.
#pragma once

#include "odomcal/solver/angles.h"
#include "odomcal/solver/camera_intrinsics_manifold.h"
#include "odomcal/solver/joint_adjustment.h"

#include <Eigen/Core>
#include <ceres/ceres.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace odomcal::internal {

// Empty string, or why the problem is invalid (kInvalidInput;
// joint_adjustment_checks.cc).
std::string CheckProblem(const JointAdjustmentProblem& problem);

// Parameter storage, the Ceres problem over it and the residual statistics.
class JointProblem {
 public:
  JointProblem(const JointAdjustmentProblem& input,
               const JointAdjustmentOptions& options);

  // The images that keep their starting pose: the first of each component.
  // Empty string, or why the problem has no determined scale.
  std::string FindGauge();

  // A point is determined by the images when two of its used observations'
  // rays (at the starting values) meet at min_triangulation_angle_deg or
  // more; the others and their observations stay out of the problem.
  void FindDeterminedPoints();

  // Builds the Ceres problem over the observations in use.
  void Build(double pixel_sigma);

  ceres::Solver::Summary Solve(int pass,
                               std::chrono::steady_clock::time_point start);

  // Reprojection residual of observation k at the current values, pixels;
  // false when the point is behind the camera.
  bool ReprojectionResidual(size_t k, Eigen::Vector2d* residual) const;

  // Estimates the pixel sigma from the observations in use (a robust scale,
  // then the inliers' mean square over their degrees of freedom), marks
  // those beyond max_sigmas unused, and returns the RMS of the inliers.
  struct PixelStatistics {
    double sigma = 0.0;
    double rms = 0.0;
    int num_inliers = 0;
    int num_marked = 0;  // observations newly left out
  };
  PixelStatistics UpdatePixelSigma(double max_sigmas, bool mark_outliers);

  // The odometry's variance factor against the links' covariances: their
  // whitened sum of squares over its degrees of freedom, 3 per link less
  // what the odometry alone determines (the metric scale, and the
  // extrinsic's yaw and x/y in part: 3 in all). Held (1) below 30 degrees
  // of freedom, within [kMinOdometryFactor, kMaxOdometryFactor].
  static constexpr double kMinOdometryFactor = 0.01;
  static constexpr double kMaxOdometryFactor = 100.0;
  double EstimateOdometryFactor();

  double OdometryFactor() const { return odometry_factor_; }

  // RobotMotionModel::kOnGround: the ground's tilt rate (rad/m) from the
  // links' out-of-plane residuals (their whitened mean square, 3 per link),
  // within [kMinGroundRate, kMaxGroundRate]; returns it.
  static constexpr double kMinGroundRate = 0.001 * kDegToRad;
  static constexpr double kMaxGroundRate = 20.0 * kDegToRad;
  double EstimateGroundRate();
  double GroundRate() const { return ground_rate_; }

  // Root mean square of the odometry residuals whitened by the links'
  // given covariances, at the current values.
  double OdometryRms() const;

  // Marginal covariance of every mount's [rotation (3), t_xy (2)]
  // (joint_adjustment.h), and the standard deviations of the refined
  // systematics.
  bool ExtrinsicCovariance(JointAdjustmentResult* result);

  void WriteResult(JointAdjustmentResult* result) const;

  // Image i's robot pose at the current values.
  Rigid3d PoseOf(size_t i) const;

  int NumDeterminedPoints() const {
    return static_cast<int>(
        std::count(determined_.begin(), determined_.end(), 1));
  }

  int NumUnused() const {
    return static_cast<int>(std::count(used_.begin(), used_.end(), 0));
  }

 private:
  const JointAdjustmentProblem& input_;
  const JointAdjustmentOptions& options_;
  // Whole robot poses (kSE3, kOnGround): tilts_ are parameters.
  bool tilted_ = false;
  bool se3_ = false;        // kSE3: links of the whole motion
  bool on_ground_ = false;  // kOnGround
  // Odometry residuals per link that measure it: 6 for a whole motion, 3
  // for a planar one (kOnGround's out-of-plane three bound the ground).
  double MeasuredLinkDof() const { return se3_ ? 6.0 : 3.0; }
  double ground_rate_ = 0.0;  // rad/m (kOnGround)
  // A planar link's residual at the current values: kOnGround's six
  // (in-plane whitened by `w`, then out of plane) or kPlanar's three.
  void PlanarLinkResidual(const OdometryLink& link,
                          const Eigen::Matrix3d& w,
                          double* residual) const;
  std::vector<std::array<double, 3>> poses_;  // x, y, yaw
  std::vector<std::array<double, 3>> tilts_;  // z, roll, pitch
  std::vector<Eigen::Vector3d> points_;
  std::vector<std::vector<double>> params_;
  // One camera's place on the robot: odom_from_cam as Ceres blocks.
  struct Mount {
    double quaternion[4] = {0.0, 0.0, 0.0, 1.0};  // x, y, z, w (Eigen's)
    double t_xy[2] = {0.0, 0.0};
    double t_z = 0.0;
  };
  // Sized once (Ceres holds pointers into it): mount 0, then other_mounts.
  std::vector<Mount> mounts_;
  double odometry_factor_ = 1.0;  // variance factor on the links
  // The odometry's systematics (JointAdjustmentProblem::systematics).
  double intrinsics_[3] = {1.0, 0.0, 0.0};
  double offset_change_s_ = 0.0;
  std::unique_ptr<ceres::SubsetManifold> intrinsics_manifold_;
  // Per camera, what of its intrinsics is refined (when refined).
  std::vector<std::unique_ptr<CameraIntrinsicsManifold>> params_manifolds_;
  std::vector<char> used_;
  // Per observation, the unit ray from its camera to its point in the
  // origin frame at the starting values.
  std::vector<Eigen::Vector3d> start_rays_;
  std::vector<char> determined_;  // per point, among the used observations
  // The residual blocks of the built problem and their clusters (the
  // observations of a point, or one link), for the robust covariance.
  std::vector<ceres::ResidualBlockId> residual_blocks_;
  std::vector<int> cluster_of_block_;
  std::vector<char> held_;
  int num_components_ = 0;
  std::unique_ptr<ceres::Problem> problem_;
  ceres::EigenQuaternionManifold quaternion_manifold_;
};

}  // namespace odomcal::internal
