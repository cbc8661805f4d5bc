// The extrinsic's covariance in the joint adjustment from its sparse
// Jacobian, without forming a dense inverse: a sparse LDL^T factor of the
// Gauss-Newton information J^T J (SuiteSparse's approximate minimum degree
// ordering: the points, each tied to a few images, go first, which is the
// Schur complement on the poses) and one solve per wanted unknown.
//
// Two covariances of the leading unknowns:
//   - the model's, (J^T J)^-1: right when every residual's noise is
//     independent and as weighted;
//   - the cluster-robust one (the sandwich H^-1 (sum_c g_c g_c^T) H^-1, with
//     g_c = J_c^T r_c the gradient of cluster c's residuals): right when
//     the residuals of a cluster are correlated, as a feature's
//     localisation errors are along its track (the same texture seen from
//     nearly the same view), which the model's counts as independent.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <vector>

namespace odomcal {

struct LeadingCovariances {
  Eigen::MatrixXd model;   // (J^T J)^-1, leading block
  Eigen::MatrixXd robust;  // the sandwich, leading block
};

// A row-major sparse Jacobian in compressed form: a SparseMatrix, or a Map
// over the arrays of another compressed row storage (ceres::CRSMatrix)
// without a copy.
using RowMajorJacobian =
    Eigen::Ref<const Eigen::SparseMatrix<double, Eigen::RowMajor>,
               Eigen::StandardCompressedFormat>;

// `jacobian`: residuals x unknowns (whitened); `residuals`: the whitened
// residuals; `cluster_of_row`: each residual's cluster (ids 0..n-1).
// False when J^T J is singular (a pivot of its unit-diagonal scaling below
// 1e-12), *covariances untouched.
bool LeadingCovariancesOf(const RowMajorJacobian& jacobian,
                          const Eigen::VectorXd& residuals,
                          const std::vector<int>& cluster_of_row,
                          int num_wanted,
                          LeadingCovariances* covariances);

}  // namespace odomcal
