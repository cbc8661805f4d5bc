// AdjustJointly: the passes of solve and noise estimation, then the
// extrinsic's covariance. The problem: joint_adjustment_internal.h.
#include "odomcal/solver/joint_adjustment.h"

#include "odomcal/solver/joint_adjustment_internal.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

namespace odomcal {
namespace {

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace

JointAdjustmentResult AdjustJointly(const JointAdjustmentProblem& problem,
                                    const JointAdjustmentOptions& options) {
  options.Check();
  JointAdjustmentResult result;
  if (const std::string why = internal::CheckProblem(problem); !why.empty()) {
    result.message = why;
    return result;
  }
  const auto start = std::chrono::steady_clock::now();
  internal::JointProblem joint(problem, options);
  if (const std::string why = joint.FindGauge(); !why.empty()) {
    result.message = why;
    return result;
  }
  if (joint.NumDeterminedPoints() == 0) {
    result.message =
        "no point is seen in two images whose rays meet at the minimum "
        "triangulation angle";
    return result;
  }
  // Pass 0 measures the start; each pass estimates the pixel sigma (and the
  // odometry's level) from its solution and drops the outliers for the
  // next.
  double pixel_sigma = options.pixel_sigma;
  const auto before =
      joint.UpdatePixelSigma(std::numeric_limits<double>::infinity(), false);
  result.reprojection_rms_px_before = before.rms;
  result.odometry_rms_sigma_before = joint.OdometryRms();
  constexpr int kMaxPasses = 4;
  constexpr double kSigmaTolerance = 0.05;
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    joint.Build(pixel_sigma);
    const ceres::Solver::Summary summary = joint.Solve(pass + 1, start);
    result.num_iterations += static_cast<int>(summary.iterations.size());
    if (summary.termination_type != ceres::CONVERGENCE) {
      result.status = JointAdjustmentStatus::kNoConvergence;
      result.message = summary.message;
      joint.WriteResult(&result);
      result.solve_time_s = SecondsSince(start);
      return result;
    }
    const bool last = pass + 1 == kMaxPasses;
    const auto statistics =
        joint.UpdatePixelSigma(options.max_reprojection_sigmas, !last);
    if (!(statistics.sigma > 0.0)) {
      result.status = JointAdjustmentStatus::kInvalidInput;
      result.message = "no observation fits its projection";
      return result;
    }
    result.reprojection_rms_px_after = statistics.rms;
    result.num_observations_used = statistics.num_inliers;
    double change = std::abs(statistics.sigma / pixel_sigma - 1.0);
    pixel_sigma = statistics.sigma;
    if (options.estimate_odometry_noise) {
      const double factor = joint.OdometryFactor();
      change = std::max(
          change,
          std::abs(std::sqrt(joint.EstimateOdometryFactor() / factor) - 1.0));
    }
    if (options.estimate_ground_tilt_rate &&
        problem.motion_model == RobotMotionModel::kOnGround) {
      const double rate = joint.GroundRate();
      change =
          std::max(change, std::abs(joint.EstimateGroundRate() / rate - 1.0));
    }
    if (change < kSigmaTolerance && statistics.num_marked == 0) break;
  }
  // The final problem at the estimated sigma, for the covariance.
  joint.Build(pixel_sigma);
  result.pixel_sigma = pixel_sigma;
  result.odometry_sigma_ratio = std::sqrt(joint.OdometryFactor());
  result.num_observations_left_out = joint.NumUnused();
  result.odometry_rms_sigma_after = joint.OdometryRms();
  joint.WriteResult(&result);
  result.solve_time_s = SecondsSince(start);
  if (!options.compute_covariance) {
    result.status = JointAdjustmentStatus::kSuccess;
    return result;
  }
  const auto covariance_start = std::chrono::steady_clock::now();
  if (!joint.ExtrinsicCovariance(&result)) {
    result.status = JointAdjustmentStatus::kSingular;
    result.message =
        "the information matrix is singular: the images and the odometry "
        "do not determine every unknown";
    return result;
  }
  result.covariance_time_s = SecondsSince(covariance_start);
  result.status = JointAdjustmentStatus::kSuccess;
  return result;
}

}  // namespace odomcal
