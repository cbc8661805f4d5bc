// Ceres problem: one 6-dimensional residual block per used motion pair over
// the parameter blocks [q (4, EigenQuaternionManifold), p_xy (2),
// log s_k (1), p_z (1, constant where z is held)], plus, for z under its
// prior, one residual block on p_z alone. The whitening W_i is
// computed once at the starting point, which keeps the cost a fixed weighted
// least-squares problem. After solving, the Jacobian is evaluated (without the
// robust loss) to form the Fisher information; it is mapped from Ceres' tangent
// coordinates to the reported ones: phi = 2 * delta for the quaternion (Plus(q,
// delta) = [cos|delta|, sin|delta| delta/|delta|] ⊗ q, a left perturbation by a
// rotation of angle 2|delta|) and ds = s * d(log s) for each scale.

#include "odomcal/solver/hand_eye_refine.h"

#include "odomcal/solver/hand_eye_cost.h"
#include "odomcal/solver/hand_eye_residual.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>

namespace odomcal {
namespace {

// (p_z - mean) / sigma: the held z as a prior.
class TranslationZPriorCost {
 public:
  TranslationZPriorCost(double mean, double sigma)
      : mean_(mean), sigma_(sigma) {}
  template <typename T>
  bool operator()(const T* p_z, T* residual) const {
    residual[0] = (p_z[0] - mean_) / sigma_;
    return true;
  }
  static ceres::CostFunction* Create(double mean, double sigma) {
    return new ceres::AutoDiffCostFunction<TranslationZPriorCost, 1, 1>(
        new TranslationZPriorCost(mean, sigma));
  }

 private:
  double mean_;
  double sigma_;
};

// Parameter storage and the Ceres problem built over it.
class HandEyeProblem {
 public:
  HandEyeProblem(const MotionPairs& pairs,
                 const std::vector<int>& indices,
                 const Rigid3d& initial,
                 const std::vector<double>& initial_scales,
                 const CalibrationOptions& options,
                 TranslationZ z,
                 bool with_loss)
      : estimate_z_(z != TranslationZ::kHold) {
    ceres::Problem::Options problem_options;
    problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    problem_ = std::make_unique<ceres::Problem>(problem_options);
    const Eigen::Quaterniond q0 = initial.rotation.normalized();
    for (int k = 0; k < 4; ++k) quaternion_[k] = q0.coeffs()[k];
    p_xy_[0] = initial.translation.x();
    p_xy_[1] = initial.translation.y();
    p_z_ =
        estimate_z_ ? initial.translation.z() : options.fixed_translation_z_m;
    for (const int index : indices) {
      const int segment = pairs[index].segment;
      log_scales_.emplace(segment, std::log(initial_scales.at(segment)));
    }
    for (const int index : indices) {
      const MotionPair& pair = pairs[index];
      const double scale = initial_scales.at(pair.segment);
      const ResidualCovarianceInScale covariance =
          HandEyeResidualCovarianceInScale(pair, initial, scale, options.noise);
      ceres::LossFunction* loss = nullptr;
      if (with_loss && options.robust_loss == RobustLoss::kHuber) {
        loss = new ceres::HuberLoss(options.robust_loss_scale);
      } else if (with_loss && options.robust_loss == RobustLoss::kCauchy) {
        loss = new ceres::CauchyLoss(options.robust_loss_scale);
      }
      pair_blocks_.push_back(
          problem_->AddResidualBlock(HandEyeCost::Create(pair, covariance),
                                     loss,
                                     quaternion_,
                                     p_xy_,
                                     &log_scales_.at(pair.segment),
                                     &p_z_));
    }
    if (z == TranslationZ::kPrior) {
      problem_->AddResidualBlock(
          TranslationZPriorCost::Create(options.fixed_translation_z_m,
                                        options.translation_z_prior_sigma_m),
          nullptr,
          &p_z_);
    }
    problem_->SetManifold(quaternion_, &quaternion_manifold_);
    if (!estimate_z_) problem_->SetParameterBlockConstant(&p_z_);
  }

  ceres::Problem& problem() { return *problem_; }

  Rigid3d OdomFromCam() const {
    return OdomFromCamParameters(quaternion_, p_xy_, p_z_);
  }

  std::vector<double> Scales(size_t num_segments) const {
    return ScalesFromLogScales(log_scales_, num_segments);
  }

  RefinementParameters Parameters() const {
    RefinementParameters parameters;
    std::copy(quaternion_, quaternion_ + 4, parameters.quaternion);
    std::copy(p_xy_, p_xy_ + 2, parameters.p_xy);
    parameters.p_z = p_z_;
    parameters.log_scales.assign(log_scales_.begin(), log_scales_.end());
    return parameters;
  }

  // False where `parameters` has other segments than this problem.
  bool SetParameters(const RefinementParameters& parameters) {
    if (parameters.log_scales.size() != log_scales_.size()) return false;
    for (const auto& [segment, log_scale] : parameters.log_scales) {
      const auto it = log_scales_.find(segment);
      if (it == log_scales_.end()) return false;
      it->second = log_scale;
    }
    std::copy(parameters.quaternion, parameters.quaternion + 4, quaternion_);
    std::copy(parameters.p_xy, parameters.p_xy + 2, p_xy_);
    p_z_ = parameters.p_z;
    return true;
  }

  // The pairs' whitened Jacobian (6 rows per pair, in `indices` order) in
  // the reported coordinates, see the file comment.
  Eigen::MatrixXd ReportedJacobian(std::vector<int>* segments) {
    ceres::Problem::EvaluateOptions evaluate_options;
    evaluate_options.apply_loss_function = false;
    evaluate_options.residual_blocks = pair_blocks_;  // not the prior
    evaluate_options.parameter_blocks = {quaternion_, p_xy_};
    segments->clear();
    for (auto& [segment, log_scale] : log_scales_) {
      evaluate_options.parameter_blocks.push_back(&log_scale);
      segments->push_back(segment);
    }
    if (estimate_z_) evaluate_options.parameter_blocks.push_back(&p_z_);
    ceres::CRSMatrix crs;
    double cost = 0.0;
    problem_->Evaluate(evaluate_options, &cost, nullptr, nullptr, &crs);
    const int num_cols = crs.num_cols;
    Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(crs.num_rows, num_cols);
    for (int row = 0; row < crs.num_rows; ++row) {
      for (int k = crs.rows[row]; k < crs.rows[row + 1]; ++k) {
        jacobian(row, crs.cols[k]) = crs.values[k];
      }
    }
    // d(tangent)/d(reported): delta = phi / 2, log s = ... ds / s.
    Eigen::VectorXd chain = Eigen::VectorXd::Ones(num_cols);
    chain.head<3>().setConstant(0.5);
    for (size_t k = 0; k < segments->size(); ++k) {
      chain(5 + k) = 1.0 / std::exp(log_scales_.at((*segments)[k]));
    }
    return jacobian * chain.asDiagonal();
  }

  // J^T J in the reported coordinates.
  Eigen::MatrixXd Information(std::vector<int>* segments) {
    const Eigen::MatrixXd jacobian = ReportedJacobian(segments);
    return jacobian.transpose() * jacobian;
  }

  // HandEyeScaleSensitivity's matrices.
  void ScaleSensitivity(const MotionPairs& pairs,
                        const std::vector<int>& indices,
                        std::vector<int>* segments,
                        Eigen::MatrixXd* information,
                        Eigen::MatrixXd* sensitivity) {
    const Eigen::MatrixXd jacobian = ReportedJacobian(segments);
    *information = jacobian.transpose() * jacobian;
    if (jacobian.rows() != 6 * static_cast<Eigen::Index>(indices.size())) {
      *sensitivity = Eigen::MatrixXd();
      return;
    }
    sensitivity->resize(jacobian.cols(),
                        static_cast<Eigen::Index>(indices.size()));
    std::map<int, Eigen::Index> column;  // of each segment's scale
    for (size_t k = 0; k < segments->size(); ++k) {
      column[(*segments)[k]] = 5 + static_cast<Eigen::Index>(k);
    }
    for (size_t p = 0; p < indices.size(); ++p) {
      const int segment = pairs[indices[p]].segment;
      const auto rows =
          jacobian.middleRows(6 * static_cast<Eigen::Index>(p), 6);
      // d r_p / d log s: the reported scale column times s.
      const Eigen::VectorXd per_log_scale =
          rows.col(column.at(segment)) * std::exp(log_scales_.at(segment));
      sensitivity->col(static_cast<Eigen::Index>(p)) =
          rows.transpose() * per_log_scale;
    }
  }

 private:
  bool estimate_z_;
  std::unique_ptr<ceres::Problem> problem_;
  std::vector<ceres::ResidualBlockId> pair_blocks_;
  ceres::EigenQuaternionManifold quaternion_manifold_;
  double quaternion_[4];  // x, y, z, w (Eigen's coeffs order)
  double p_xy_[2];
  double p_z_;
  std::map<int, double> log_scales_;
};

bool ValidStart(const std::vector<int>& indices,
                const MotionPairs& pairs,
                const std::vector<double>& scales) {
  for (const int index : indices) {
    const int segment = pairs[index].segment;
    if (segment < 0 || static_cast<size_t>(segment) >= scales.size() ||
        !(scales[segment] > 0.0) || !std::isfinite(scales[segment])) {
      return false;
    }
  }
  return true;
}

}  // namespace

RefinementResult RefineOdomFromCam(const MotionPairs& pairs,
                                   const std::vector<int>& indices,
                                   const Rigid3d& initial,
                                   const std::vector<double>& initial_scales,
                                   const CalibrationOptions& options,
                                   TranslationZ z,
                                   InformationAtSolution information) {
  RefinementResult result;
  result.odom_from_cam = initial;
  result.metric_scales = initial_scales;
  if (indices.empty() || !ValidStart(indices, pairs, initial_scales) ||
      !IsFinite(initial)) {
    result.report = "invalid starting point (non-positive or missing scale)";
    return result;
  }
  HandEyeProblem problem(
      pairs, indices, initial, initial_scales, options, z, /*with_loss=*/true);
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = options.max_num_iterations;
  solver_options.function_tolerance = 1e-15;
  solver_options.gradient_tolerance = 1e-15;
  solver_options.parameter_tolerance = 1e-15;
  solver_options.logging_type = ceres::SILENT;
  solver_options.minimizer_progress_to_stdout = false;
  solver_options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem.problem(), &summary);

  result.usable = summary.IsSolutionUsable();
  result.num_iterations = static_cast<int>(summary.iterations.size()) - 1;
  result.initial_cost = summary.initial_cost;
  result.final_cost = summary.final_cost;
  result.report = summary.BriefReport();
  if (!result.usable) {
    return result;
  }
  result.odom_from_cam = problem.OdomFromCam();
  result.metric_scales = problem.Scales(initial_scales.size());
  result.parameters = problem.Parameters();
  if (information == InformationAtSolution::kCompute) {
    result.information = problem.Information(&result.information_segments);
  }
  return result;
}

Eigen::MatrixXd RefinementInformation(const MotionPairs& pairs,
                                      const std::vector<int>& indices,
                                      const Rigid3d& initial,
                                      const std::vector<double>& initial_scales,
                                      const CalibrationOptions& options,
                                      TranslationZ z,
                                      const RefinementResult& refined,
                                      std::vector<int>* information_segments) {
  information_segments->clear();
  if (!refined.usable || indices.empty() ||
      !ValidStart(indices, pairs, initial_scales) || !IsFinite(initial)) {
    return Eigen::MatrixXd();
  }
  HandEyeProblem problem(
      pairs, indices, initial, initial_scales, options, z, /*with_loss=*/true);
  if (!problem.SetParameters(refined.parameters)) return Eigen::MatrixXd();
  return problem.Information(information_segments);
}

Eigen::MatrixXd HandEyeInformation(const MotionPairs& pairs,
                                   const std::vector<int>& indices,
                                   const Rigid3d& odom_from_cam,
                                   const std::vector<double>& metric_scales,
                                   const CalibrationOptions& options,
                                   std::vector<int>* information_segments,
                                   TranslationZ z) {
  if (indices.empty() || !ValidStart(indices, pairs, metric_scales)) {
    information_segments->clear();
    return Eigen::MatrixXd();
  }
  HandEyeProblem problem(pairs,
                         indices,
                         odom_from_cam,
                         metric_scales,
                         options,
                         z,
                         /*with_loss=*/false);
  return problem.Information(information_segments);
}

HandEyeSensitivity HandEyeScaleSensitivity(
    const MotionPairs& pairs,
    const std::vector<int>& indices,
    const Rigid3d& odom_from_cam,
    const std::vector<double>& metric_scales,
    const CalibrationOptions& options,
    TranslationZ z) {
  HandEyeSensitivity result;
  if (indices.empty() || !ValidStart(indices, pairs, metric_scales)) {
    return result;
  }
  HandEyeProblem problem(pairs,
                         indices,
                         odom_from_cam,
                         metric_scales,
                         options,
                         z,
                         /*with_loss=*/false);
  problem.ScaleSensitivity(pairs,
                           indices,
                           &result.information_segments,
                           &result.information,
                           &result.scale_sensitivity);
  return result;
}

}  // namespace odomcal
