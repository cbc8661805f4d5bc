// The Kenward-Roger widening of the estimate's covariance for the estimated
// noise: the term A (noise_estimation_internal.h) and its application to the
// refinement's information (WidenForEstimatedNoise).

#include "odomcal/solver/noise_estimation.h"
#include "odomcal/solver/noise_estimation_internal.h"
#include "odomcal/solver/parallel_chunks.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <vector>

namespace odomcal {
namespace internal {

Eigen::MatrixXd KenwardRogerTerm(const std::vector<PairTerms>& terms,
                                 const ParameterOf& parameter_of,
                                 const Eigen::VectorXd& mu,
                                 const Eigen::MatrixXd& multiplier_covariance,
                                 int num_threads) {
  const int num_free = static_cast<int>(mu.size());
  const Eigen::VectorXd all = WithFixedParameter(mu);
  const int num_pairs = static_cast<int>(terms.size());
  const int num_columns = static_cast<int>(terms.front().jacobian.cols());
  const Eigen::MatrixXd zero = Eigen::MatrixXd::Zero(num_columns, num_columns);
  // Per chunk of pairs (parallel_chunks.h): the normal matrix, P_p and
  // sum_pq W_pq Q_pq, the last summed per pair as sum_p (D_p P J)^T (sum_q
  // W_pq P D_q P J): num_free products per pair instead of num_free^2.
  struct Sums {
    Eigen::MatrixXd normal;
    std::vector<Eigen::MatrixXd> first;  // P_p
    Eigen::MatrixXd weighted_second;
  };
  const Sums zero_sums{
      zero, std::vector<Eigen::MatrixXd>(num_free, zero), zero};
  std::vector<Sums> chunk_sums(NumChunks(num_pairs), zero_sums);
  ForEachChunk(num_pairs, num_threads, [&](int chunk, int begin, int end) {
    Sums& sums = chunk_sums[chunk];
    std::vector<Matrix6d> derivatives(num_free);
    std::vector<Matrix6X> pdpj(num_free, Matrix6X(6, num_columns));
    std::vector<Matrix6X> ppdpj(num_free, Matrix6X(6, num_columns));
    Matrix6X pj(6, num_columns);
    Matrix6X weighted(6, num_columns);
    for (int i = begin; i < end; ++i) {
      const PairTerms& term = terms[i];
      const Matrix6d covariance =
          PairCovariance(term, parameter_of, all, derivatives.data());
      const Matrix6d precision = covariance.ldlt().solve(Matrix6d::Identity());
      pj.noalias() = precision * term.jacobian;
      sums.normal.noalias() += term.jacobian.transpose() * pj;
      for (int p = 0; p < num_free; ++p) {
        pdpj[p].noalias() = derivatives[p] * pj;
        ppdpj[p].noalias() = precision * pdpj[p];
        sums.first[p].noalias() += pj.transpose() * pdpj[p];
      }
      for (int p = 0; p < num_free; ++p) {
        weighted.setZero();
        for (int q = 0; q < num_free; ++q) {
          const double w = multiplier_covariance(p, q);
          if (w != 0.0) weighted += w * ppdpj[q];
        }
        sums.weighted_second.noalias() += pdpj[p].transpose() * weighted;
      }
    }
  });
  Sums total = zero_sums;
  for (const Sums& sums : chunk_sums) {
    total.normal += sums.normal;
    for (int p = 0; p < num_free; ++p) total.first[p] += sums.first[p];
    total.weighted_second += sums.weighted_second;
  }
  const Eigen::MatrixXd& normal = total.normal;
  const std::vector<Eigen::MatrixXd>& first = total.first;
  const Eigen::MatrixXd& weighted_second = total.weighted_second;
  const Eigen::MatrixXd phi =
      normal.completeOrthogonalDecomposition().pseudoInverse();
  Eigen::MatrixXd term = weighted_second;
  for (int p = 0; p < num_free; ++p) {
    for (int q = 0; q < num_free; ++q) {
      const double w = multiplier_covariance(p, q);
      if (w == 0.0) continue;
      term -= w * (first[p] * phi * first[q]);
    }
  }
  return 0.5 * (term + term.transpose());
}

}  // namespace internal

Eigen::MatrixXd WidenForEstimatedNoise(
    const Eigen::MatrixXd& information,
    const std::vector<int>& information_segments,
    const NoiseEstimate& estimate,
    double* stddev_widening) {
  if (stddev_widening) *stddev_widening = 1.0;
  const Eigen::MatrixXd& term = estimate.kenward_roger_term;
  const int n = static_cast<int>(information.rows());
  if (term.size() == 0 || n < 5) return information;
  // Column of `term` for each column of `information` (-1: none).
  std::vector<int> source(n, -1);
  for (int k = 0; k < 5; ++k) source[k] = k;
  for (size_t k = 0; k < information_segments.size() && 5 + k < source.size();
       ++k) {
    const auto found = std::find(estimate.kenward_roger_segments.begin(),
                                 estimate.kenward_roger_segments.end(),
                                 information_segments[k]);
    if (found != estimate.kenward_roger_segments.end()) {
      source[5 + k] =
          5 + static_cast<int>(found - estimate.kenward_roger_segments.begin());
    }
  }
  Eigen::MatrixXd mapped = Eigen::MatrixXd::Zero(n, n);
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) {
      if (source[r] >= 0 && source[c] >= 0 && source[r] < term.rows() &&
          source[c] < term.cols()) {
        mapped(r, c) = term(source[r], source[c]);
      }
    }
  }
  Eigen::MatrixXd widened = information * (information + 2.0 * mapped)
                                              .completeOrthogonalDecomposition()
                                              .solve(information);
  widened = 0.5 * (widened + widened.transpose());
  if (stddev_widening) {
    const Eigen::VectorXd before = information.completeOrthogonalDecomposition()
                                       .pseudoInverse()
                                       .diagonal();
    const Eigen::VectorXd after =
        widened.completeOrthogonalDecomposition().pseudoInverse().diagonal();
    for (int k = 0; k < n; ++k) {
      if (before(k) > 0.0 && std::isfinite(after(k))) {
        *stddev_widening =
            std::max(*stddev_widening, std::sqrt(after(k) / before(k)));
      }
    }
  }
  return widened;
}

}  // namespace odomcal
