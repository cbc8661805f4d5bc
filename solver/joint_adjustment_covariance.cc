#include "odomcal/solver/joint_adjustment_covariance.h"

#include <Eigen/SparseCholesky>

#include <cmath>

namespace odomcal {

bool LeadingBlockOfInverseInformation(
    const Eigen::SparseMatrix<double, Eigen::RowMajor>& jacobian,
    int num_wanted,
    Eigen::MatrixXd* block) {
  const Eigen::Index num_unknowns = jacobian.cols();
  if (num_wanted < 1 || num_wanted > num_unknowns) return false;
  Eigen::SparseMatrix<double> information =
      Eigen::SparseMatrix<double>(jacobian.transpose()) * jacobian;
  // Scaled to a unit diagonal, so that the pivot test does not depend on the
  // unknowns' units (a pixel against a metre) or on how many observations
  // each has: H = S^-1 H_s S^-1, so H^-1 = S H_s^-1 S.
  Eigen::VectorXd scale(num_unknowns);
  for (Eigen::Index k = 0; k < num_unknowns; ++k) {
    const double diagonal = information.coeff(k, k);
    if (!(diagonal > 0.0)) return false;  // an unknown nothing sees
    scale[k] = 1.0 / std::sqrt(diagonal);
  }
  information = scale.asDiagonal() * information * scale.asDiagonal();
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>,
                        Eigen::Lower,
                        Eigen::AMDOrdering<int>>
      ldlt(information);
  if (ldlt.info() != Eigen::Success) return false;
  constexpr double kMinPivot = 1e-12;
  if (!(ldlt.vectorD().minCoeff() > kMinPivot)) return false;
  const Eigen::MatrixXd unit =
      Eigen::MatrixXd::Identity(num_unknowns, num_wanted);
  const Eigen::MatrixXd columns = ldlt.solve(unit);
  if (ldlt.info() != Eigen::Success || !columns.allFinite()) return false;
  const Eigen::VectorXd leading_scale = scale.head(num_wanted);
  const Eigen::MatrixXd leading = leading_scale.asDiagonal() *
                                  columns.topRows(num_wanted) *
                                  leading_scale.asDiagonal();
  *block = 0.5 * (leading + leading.transpose());
  return true;
}

}  // namespace odomcal
