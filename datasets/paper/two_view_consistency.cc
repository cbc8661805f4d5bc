#include "odomcal/datasets/paper/two_view_consistency.h"

#include "odomcal/solver/angles.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace odomcal {
namespace {

// Value at fraction `q` of the sorted samples (nearest rank).
double Quantile(const std::vector<double>& sorted, double q) {
  const size_t index = static_cast<size_t>(
      std::ceil(q * static_cast<double>(sorted.size())) - 1.0);
  return sorted[std::min(index, sorted.size() - 1)];
}

}  // namespace

void AddTwoViewErrors(const PaperSimulation& simulation,
                      TwoViewErrors* errors) {
  for (size_t k = 0; k < simulation.pairs.size(); ++k) {
    const MotionPair& measured = simulation.pairs[k];
    if (!measured.cam_covariance || simulation.is_outlier[k]) continue;
    const Rigid3d& truth = simulation.true_pairs[k].cam_i_from_cam_j;
    const Rigid3d& estimate = measured.cam_i_from_cam_j;
    // The covariance is of the estimate at its reported length: compare the
    // true direction at that length.
    const double length = estimate.translation.norm();
    if (!(length > 0.0) || !(truth.translation.norm() > 0.0)) continue;
    Eigen::Matrix<double, 6, 1> error;
    error.head<3>() =
        LogRotation(truth.rotation * estimate.rotation.conjugate());
    error.tail<3>() =
        length * truth.translation.normalized() - estimate.translation;
    // Rank 5: whiten with the pseudo-inverse, dropping the null direction
    // (along the translation).
    const Eigen::SelfAdjointEigenSolver<MotionCovariance> eigen(
        *measured.cam_covariance);
    double nees = 0.0;
    for (int d = 1; d < 6; ++d) {
      const double projection = eigen.eigenvectors().col(d).dot(error);
      nees += projection * projection / eigen.eigenvalues()(d);
    }
    errors->nees.push_back(nees);
    const double cosine = std::clamp(
        truth.translation.normalized().dot(estimate.translation / length),
        -1.0,
        1.0);
    errors->direction_error_deg.push_back(std::acos(cosine) * kRadToDeg);
  }
}

TwoViewConsistency SummarizeTwoViewErrors(const TwoViewErrors& errors) {
  TwoViewConsistency summary;
  summary.num_motions = static_cast<int>(errors.nees.size());
  if (errors.nees.empty()) return summary;
  std::vector<double> sorted = errors.nees;
  std::sort(sorted.begin(), sorted.end());
  summary.nees_median = Quantile(sorted, 0.5);
  summary.nees_quantile_90 = Quantile(sorted, 0.9);
  summary.nees_quantile_99 = Quantile(sorted, 0.99);
  summary.nees_max = sorted.back();
  const auto num_gross = std::count_if(
      errors.direction_error_deg.begin(),
      errors.direction_error_deg.end(),
      [](double error) { return error > kGrossDirectionErrorDeg; });
  summary.gross_error_rate =
      static_cast<double>(num_gross) / static_cast<double>(summary.num_motions);
  return summary;
}

}  // namespace odomcal
