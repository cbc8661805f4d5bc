#include "odomcal/solver/joint_adjustment_covariance.h"

#include <amd.h>

#include <Eigen/SparseCholesky>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace odomcal {
namespace {

using Permutation =
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int>;

// A fill-reducing order of the unknowns of the symmetric `information` by
// SuiteSparse's AMD: the permutation P with (P x)[k] the unknown eliminated
// k-th. Eigen's own port of AMD reads out of bounds on adjustments of a
// million unknowns (four cameras of 290 images, 270 000 points). False
// where AMD fails (out of memory).
bool FillReducingOrder(const Eigen::SparseMatrix<double>& information,
                       Permutation* permutation) {
  const int n = static_cast<int>(information.cols());
  std::vector<int> order(static_cast<size_t>(n));
  std::array<double, AMD_CONTROL> control{};
  std::array<double, AMD_INFO> info{};
  amd_defaults(control.data());
  const int status = amd_order(n,
                               information.outerIndexPtr(),
                               information.innerIndexPtr(),
                               order.data(),
                               control.data(),
                               info.data());
  if (status != AMD_OK && status != AMD_OK_BUT_JUMBLED) return false;
  permutation->resize(n);
  for (int k = 0; k < n; ++k) permutation->indices()[order[k]] = k;
  return true;
}

}  // namespace

bool LeadingCovariancesOf(const RowMajorJacobian& jacobian,
                          const Eigen::VectorXd& residuals,
                          const std::vector<int>& cluster_of_row,
                          int num_wanted,
                          LeadingCovariances* covariances) {
  const Eigen::Index num_unknowns = jacobian.cols();
  if (num_wanted < 1 || num_wanted > num_unknowns ||
      residuals.size() != jacobian.rows() ||
      cluster_of_row.size() != static_cast<size_t>(jacobian.rows())) {
    return false;
  }
  // H = J^T J with one column-major copy of J: the row-major J's arrays,
  // read as a column-major matrix, are J^T.
  Eigen::SparseMatrix<double> information;
  {
    const Eigen::SparseMatrix<double> jacobian_by_column = jacobian;
    const Eigen::Map<const Eigen::SparseMatrix<double>> transposed(
        jacobian.cols(),
        jacobian.rows(),
        jacobian.nonZeros(),
        jacobian.outerIndexPtr(),
        jacobian.innerIndexPtr(),
        jacobian.valuePtr());
    information = transposed * jacobian_by_column;
  }
  // Scaled to a unit diagonal, so that the pivot test does not depend on the
  // unknowns' units (a pixel against a metre) or on how many observations
  // each has: H = S^-1 H_s S^-1, so H^-1 = S H_s^-1 S. In place.
  Eigen::VectorXd scale(num_unknowns);
  for (Eigen::Index k = 0; k < num_unknowns; ++k) {
    const double diagonal = information.coeff(k, k);
    if (!(diagonal > 0.0)) return false;  // an unknown nothing sees
    scale[k] = 1.0 / std::sqrt(diagonal);
  }
  for (Eigen::Index k = 0; k < information.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(information, k); it;
         ++it) {
      it.valueRef() *= scale[it.row()] * scale[it.col()];
    }
  }
  // Factored in AMD's order: P H_s P^T = L D L^T.
  Permutation permutation;
  information.makeCompressed();
  if (!FillReducingOrder(information, &permutation)) return false;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>,
                        Eigen::Lower,
                        Eigen::NaturalOrdering<int>>
      ldlt;
  {
    Eigen::SparseMatrix<double> ordered;
    ordered = information.twistedBy(permutation);
    information.resize(0, 0);
    information.data().squeeze();
    ldlt.compute(ordered);
  }
  if (ldlt.info() != Eigen::Success) return false;
  constexpr double kMinPivot = 1e-12;
  if (!(ldlt.vectorD().minCoeff() > kMinPivot)) return false;
  const Eigen::MatrixXd unit =
      permutation * Eigen::MatrixXd::Identity(num_unknowns, num_wanted);
  // Columns of H^-1 for the wanted unknowns: S H_s^-1 S e_k, with
  // H_s^-1 = P^T (P H_s P^T)^-1 P.
  Eigen::MatrixXd columns = ldlt.solve(unit);
  if (ldlt.info() != Eigen::Success || !columns.allFinite()) return false;
  columns = permutation.transpose() * columns;
  columns = scale.asDiagonal() * columns;
  columns *= scale.head(num_wanted).asDiagonal();
  const Eigen::MatrixXd model = columns.topRows(num_wanted);
  covariances->model = 0.5 * (model + model.transpose());
  // Per cluster, v_c = (H^-1 g_c) restricted to the wanted unknowns =
  // columns^T J_c^T r_c; the sandwich is sum_c v_c v_c^T.
  const int num_clusters =
      cluster_of_row.empty()
          ? 0
          : *std::max_element(cluster_of_row.begin(), cluster_of_row.end()) + 1;
  Eigen::MatrixXd projected(num_wanted, num_clusters);
  projected.setZero();
  for (Eigen::Index row = 0; row < jacobian.rows(); ++row) {
    const int cluster = cluster_of_row[row];
    for (RowMajorJacobian::InnerIterator it(jacobian, row); it; ++it) {
      projected.col(cluster) +=
          columns.row(it.col()).transpose() * (it.value() * residuals[row]);
    }
  }
  covariances->robust = projected * projected.transpose();
  return true;
}

}  // namespace odomcal
