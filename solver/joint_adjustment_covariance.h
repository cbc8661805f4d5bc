// The leading block of the inverse Gauss-Newton information (J^T J)^-1 of a
// sparse Jacobian: the marginal covariance of the first unknowns over all
// the others, without forming the dense inverse. A sparse LDL^T factor
// (approximate minimum degree ordering: the points, each tied to a few
// images, go first, which is the Schur complement on the poses) and one
// solve per wanted column.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace odomcal {

// `jacobian`: residuals x unknowns. `*block`: the leading num_wanted x
// num_wanted block of (J^T J)^-1. False when J^T J is singular (a pivot
// of its unit-diagonal scaling below 1e-12), *block untouched.
bool LeadingBlockOfInverseInformation(
    const Eigen::SparseMatrix<double, Eigen::RowMajor>& jacobian,
    int num_wanted,
    Eigen::MatrixXd* block);

}  // namespace odomcal
