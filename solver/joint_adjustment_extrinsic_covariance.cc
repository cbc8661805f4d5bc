// The joint adjustment's extrinsic covariance at its solution
// (joint_adjustment_internal.h): Ceres' Jacobian handed to
// LeadingCovariancesOf (joint_adjustment_covariance.h).
#include "odomcal/solver/joint_adjustment_covariance.h"
#include "odomcal/solver/joint_adjustment_internal.h"

#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <set>

namespace odomcal::internal {

bool JointProblem::ExtrinsicCovariance(JointAdjustmentResult* result) {
  // A mount whose images kept no observation has no block: undetermined.
  std::vector<double*> blocks;
  for (Mount& mount : mounts_) {
    if (!problem_->HasParameterBlock(mount.quaternion)) return false;
    blocks.push_back(mount.quaternion);
    blocks.push_back(mount.t_xy);
  }
  const auto free = [&](double* block) {
    return problem_->HasParameterBlock(block) &&
           !problem_->IsParameterBlockConstant(block);
  };
  // After the mounts: the offset's change, then the free intrinsics.
  const int num_extrinsic = 5 * static_cast<int>(mounts_.size());
  int num_wanted = num_extrinsic;
  const bool offset_free = free(&offset_change_s_);
  if (offset_free) {
    blocks.push_back(&offset_change_s_);
    ++num_wanted;
  }
  const bool intrinsics_free = free(intrinsics_);
  if (intrinsics_free) {
    blocks.push_back(intrinsics_);
    num_wanted += problem_->ParameterBlockTangentSize(intrinsics_);
  }
  const std::set<const double*> leading(blocks.begin(), blocks.end());
  std::vector<double*> others;
  problem_->GetParameterBlocks(&others);
  for (double* block : others) {
    if (leading.count(block) != 0) continue;
    if (problem_->IsParameterBlockConstant(block)) continue;
    blocks.push_back(block);
  }
  ceres::Problem::EvaluateOptions evaluate_options;
  evaluate_options.parameter_blocks = blocks;
  evaluate_options.residual_blocks = residual_blocks_;
  evaluate_options.apply_loss_function = true;
  evaluate_options.num_threads = options_.num_threads;
  ceres::CRSMatrix jacobian;
  std::vector<double> residuals;
  if (!problem_->Evaluate(
          evaluate_options, nullptr, &residuals, nullptr, &jacobian)) {
    return false;
  }
  std::vector<int> cluster_of_row;
  cluster_of_row.reserve(residuals.size());
  for (size_t b = 0; b < residual_blocks_.size(); ++b) {
    const int size =
        problem_->GetCostFunctionForResidualBlock(residual_blocks_[b])
            ->num_residuals();
    cluster_of_row.insert(cluster_of_row.end(), size, cluster_of_block_[b]);
  }
  // Ceres' compressed rows (sorted columns) read in place.
  const Eigen::Map<const Eigen::SparseMatrix<double, Eigen::RowMajor>> sparse(
      jacobian.num_rows,
      jacobian.num_cols,
      static_cast<Eigen::Index>(jacobian.values.size()),
      jacobian.rows.data(),
      jacobian.cols.data(),
      jacobian.values.data());
  LeadingCovariances covariances;
  if (!LeadingCovariancesOf(
          sparse,
          Eigen::Map<const Eigen::VectorXd>(
              residuals.data(), static_cast<Eigen::Index>(residuals.size())),
          cluster_of_row,
          num_wanted,
          &covariances)) {
    return false;
  }
  // Widened per unknown to the cluster-robust standard deviation where
  // that is larger (correlated errors along tracks), never narrowed.
  Eigen::VectorXd widening(num_wanted);
  for (int k = 0; k < num_wanted; ++k) {
    widening[k] = std::max(
        1.0, std::sqrt(covariances.robust(k, k) / covariances.model(k, k)));
  }
  const Eigen::MatrixXd widened =
      widening.asDiagonal() * covariances.model * widening.asDiagonal();
  result->mounts_covariance_widening = widening.head(num_extrinsic);
  result->covariance_widening = widening.head<5>();
  // Ceres' quaternion tangent delta is half the rotation vector.
  Eigen::VectorXd to_reported = Eigen::VectorXd::Ones(num_extrinsic);
  for (int m = 0; m < num_extrinsic; m += 5) to_reported.segment<3>(m) *= 2.0;
  result->mounts_covariance =
      to_reported.asDiagonal() *
      widened.topLeftCorner(num_extrinsic, num_extrinsic) *
      to_reported.asDiagonal();
  result->covariance = result->mounts_covariance.topLeftCorner<5, 5>();
  int row = num_extrinsic;
  if (offset_free) {
    result->time_offset_change_stddev_s = std::sqrt(widened(row, row));
    ++row;
  }
  if (intrinsics_free) {
    // The subset manifold's tangent lists the free intrinsics in order.
    for (int k = 0; k < 3; ++k) {
      if (!input_.systematics->refine_intrinsics[k]) continue;
      result->intrinsics_stddev[k] = std::sqrt(widened(row, row));
      ++row;
    }
  }
  return true;
}

}  // namespace odomcal::internal
