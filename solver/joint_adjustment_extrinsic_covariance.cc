// The joint adjustment's extrinsic covariance at its solution
// (joint_adjustment_internal.h): Ceres' Jacobian handed to
// LeadingCovariancesOf (joint_adjustment_covariance.h).
#include "odomcal/solver/joint_adjustment_covariance.h"
#include "odomcal/solver/joint_adjustment_internal.h"

#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>

namespace odomcal::internal {

bool JointProblem::ExtrinsicCovariance(JointAdjustmentResult* result) {
  std::vector<double*> blocks = {quaternion_, t_xy_};
  const auto free = [&](double* block) {
    return problem_->HasParameterBlock(block) &&
           !problem_->IsParameterBlockConstant(block);
  };
  // After the extrinsic: the offset's change, then the free intrinsics.
  int num_wanted = 5;
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
  std::vector<double*> others;
  problem_->GetParameterBlocks(&others);
  for (double* block : others) {
    if (block == quaternion_ || block == t_xy_ || block == &offset_change_s_ ||
        block == intrinsics_) {
      continue;
    }
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
  const Eigen::MatrixXd leading =
      widening.asDiagonal() * covariances.model * widening.asDiagonal();
  result->covariance_widening = widening.head<5>();
  // Ceres' quaternion tangent delta is half the rotation vector.
  Eigen::Matrix<double, 5, 5> to_reported =
      Eigen::Matrix<double, 5, 5>::Identity();
  to_reported.topLeftCorner<3, 3>() *= 2.0;
  result->covariance =
      to_reported * leading.topLeftCorner<5, 5>() * to_reported.transpose();
  int row = 5;
  if (offset_free) {
    result->time_offset_change_stddev_s = std::sqrt(leading(row, row));
    ++row;
  }
  if (intrinsics_free) {
    // The subset manifold's tangent lists the free intrinsics in order.
    for (int k = 0; k < 3; ++k) {
      if (!input_.systematics->refine_intrinsics[k]) continue;
      result->intrinsics_stddev[k] = std::sqrt(leading(row, row));
      ++row;
    }
  }
  return true;
}

}  // namespace odomcal::internal
