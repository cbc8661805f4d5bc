#include "odomcal/solver/joint_adjustment_covariance.h"

#include <Eigen/SparseCholesky>

namespace odomcal {

bool LeadingBlockOfInverseInformation(
    const Eigen::SparseMatrix<double, Eigen::RowMajor>& jacobian,
    int num_wanted,
    Eigen::MatrixXd* block) {
  const Eigen::Index num_unknowns = jacobian.cols();
  if (num_wanted < 1 || num_wanted > num_unknowns) return false;
  const Eigen::SparseMatrix<double> information =
      Eigen::SparseMatrix<double>(jacobian.transpose()) * jacobian;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>,
                        Eigen::Lower,
                        Eigen::AMDOrdering<int>>
      ldlt(information);
  if (ldlt.info() != Eigen::Success) return false;
  const Eigen::VectorXd pivots = ldlt.vectorD();
  constexpr double kMinRelativePivot = 1e-12;
  const double largest = pivots.cwiseAbs().maxCoeff();
  if (!(largest > 0.0) || pivots.minCoeff() <= kMinRelativePivot * largest) {
    return false;
  }
  const Eigen::MatrixXd unit =
      Eigen::MatrixXd::Identity(num_unknowns, num_wanted);
  const Eigen::MatrixXd columns = ldlt.solve(unit);
  if (ldlt.info() != Eigen::Success || !columns.allFinite()) return false;
  const Eigen::MatrixXd leading = columns.topRows(num_wanted);
  *block = 0.5 * (leading + leading.transpose());
  return true;
}

}  // namespace odomcal
