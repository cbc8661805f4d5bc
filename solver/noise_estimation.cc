// Variance-component estimation, see noise_estimation.h: the Fisher scoring
// of the parameters' multipliers (noise_estimation_internal.h), their
// uncertainty and the tie decisions. The per-pair terms, the Kenward-Roger
// term and the summary are in noise_pair_terms.cc, noise_kenward_roger.cc
// and noise_summary.cc.

#include "odomcal/solver/noise_estimation.h"

#include "odomcal/solver/hand_eye_residual.h"
#include "odomcal/solver/noise_estimation_internal.h"
#include "odomcal/solver/parallel_chunks.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <utility>

namespace odomcal {
namespace {

using internal::Contribution;
using internal::CovariancePart;
using internal::ForEachChunk;
using internal::Index;
using internal::InterpolationContribution;
using internal::kCoupled;
using internal::KenwardRogerTerm;
using internal::kNumCoupled;
using internal::Matrix6X;
using internal::NumChunks;
using internal::PairCovariance;
using internal::PairCovarianceDerivatives;
using internal::PairTerms;
using internal::ParameterOf;
using internal::ResidualJacobian;
using internal::WithFixedParameter;

constexpr int kMaxIterations = 100;
constexpr double kConvergence = 1e-5;
// The bounds of the estimated standard deviations (noise_estimation.h), as
// multipliers of the variances. Exact or over-fitted data (simulations, a
// handful of pairs) would otherwise claim a near-zero noise, a covariance of
// zero and a gate that rejects every pair off by rounding; a systematic
// error, a noise without bound.
constexpr double kMinMultiplier = kNoiseSigmaRatioFloor * kNoiseSigmaRatioFloor;
constexpr double kMaxMultiplier =
    kNoiseSigmaRatioCeiling * kNoiseSigmaRatioCeiling;
// Relative distance to a bound within which a multiplier counts as at it.
constexpr double kAtBound = 1e-3;
// The largest change of a multiplier, as a ratio, that a Fisher step may
// make.
constexpr double kMaxFisherRatio = 4.0;
// Fisher steps before an unseparable parameter is tied without converging.
constexpr int kIterationsBeforeTieCheck = 3;

// Sums of one pass over the pairs at the given parameter multipliers.
struct Pass {
  Eigen::VectorXd weighted_sum;     // q_p = sum e^T P D_p P e
  Eigen::VectorXd redundancy_part;  // t_p = sum tr(D_p M)
  Eigen::MatrixXd helmert;          // H_pq = sum tr(M D_p M D_q)
  double chi_square = 0.0;          // sum e^T P e
};

// The prior (noise_estimation.h): w pseudo-observations of each parameter's
// starting level (multiplier 1), log p(mu) = -w/2 (log mu + 1 / mu). In the
// units of the score q - t (twice the log-likelihood's derivative) it adds
// w / mu^2 to q, w / mu to t and w / mu^2 to H (the information of w
// observations, as a linear component's redundancy r adds r / mu^2):
// Helmert's step for one linear component then gives (S + w) / (r + w).
Pass WithPrior(Pass pass, const Eigen::VectorXd& mu, double weight) {
  for (int p = 0; p < mu.size(); ++p) {
    pass.weighted_sum(p) += weight / (mu(p) * mu(p));
    pass.redundancy_part(p) += weight / mu(p);
    pass.helmert(p, p) += weight / (mu(p) * mu(p));
  }
  return pass;
}

// mu: one multiplier per free parameter. Two passes over the pairs (the
// normal matrix first, then the sums that need its inverse), each pair's
// covariance derivatives evaluated in the second: kept for all pairs, they
// would take num_free * 288 bytes per pair. Each pass sums per chunk of
// pairs, the chunks in order (parallel_chunks.h).
Pass Evaluate(const std::vector<PairTerms>& terms,
              const ParameterOf& parameter_of,
              const Eigen::VectorXd& mu,
              int num_threads) {
  const int num_free = static_cast<int>(mu.size());
  const Eigen::VectorXd all = WithFixedParameter(mu);
  const int num_pairs = static_cast<int>(terms.size());
  const int num_columns = static_cast<int>(terms.front().jacobian.cols());
  const int num_chunks = NumChunks(num_pairs);
  std::vector<Matrix6d> precisions(terms.size());
  std::vector<Eigen::MatrixXd> chunk_normals(
      num_chunks, Eigen::MatrixXd::Zero(num_columns, num_columns));
  ForEachChunk(num_pairs, num_threads, [&](int chunk, int begin, int end) {
    Matrix6X pj(6, num_columns);
    for (int i = begin; i < end; ++i) {
      const Matrix6d covariance =
          PairCovariance(terms[i], parameter_of, all, nullptr);
      precisions[i] = covariance.ldlt().solve(Matrix6d::Identity());
      pj.noalias() = precisions[i] * terms[i].jacobian;
      chunk_normals[chunk].noalias() += terms[i].jacobian.transpose() * pj;
    }
  });
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(num_columns, num_columns);
  for (const Eigen::MatrixXd& chunk_normal : chunk_normals) {
    normal += chunk_normal;
  }
  const Eigen::MatrixXd normal_inverse =
      normal.completeOrthogonalDecomposition().pseudoInverse();
  // tr(A B) without forming A B: the sum of A .* B^T (36 products, not 216).
  const auto trace_of_product = [](const Matrix6d& a, const Matrix6d& b) {
    return a.cwiseProduct(b.transpose()).sum();
  };
  Pass zero;
  zero.weighted_sum = Eigen::VectorXd::Zero(num_free);
  zero.redundancy_part = Eigen::VectorXd::Zero(num_free);
  zero.helmert = Eigen::MatrixXd::Zero(num_free, num_free);
  std::vector<Pass> chunk_passes(num_chunks, zero);
  ForEachChunk(num_pairs, num_threads, [&](int chunk, int begin, int end) {
    Pass& pass = chunk_passes[chunk];
    std::vector<Matrix6d> derivatives(num_free);
    std::vector<Matrix6d> md(num_free);
    Matrix6X pj(6, num_columns);
    Matrix6X pj_normal_inverse(6, num_columns);
    for (int i = begin; i < end; ++i) {
      PairCovarianceDerivatives(
          terms[i], parameter_of, all, derivatives.data());
      const Matrix6d& p = precisions[i];
      pj.noalias() = p * terms[i].jacobian;
      pj_normal_inverse.noalias() = pj * normal_inverse;
      Matrix6d m = p;
      m.noalias() -= pj_normal_inverse * pj.transpose();
      const Vector6d pe = p * terms[i].residual;
      pass.chi_square += terms[i].residual.dot(pe);
      for (int c = 0; c < num_free; ++c) {
        const Matrix6d& d = derivatives[c];
        pass.weighted_sum(c) += pe.dot(d * pe);
        pass.redundancy_part(c) += trace_of_product(d, m);
        md[c].noalias() = m * d;
      }
      // H is symmetric: tr(M D_c M D_d) = tr(M D_d M D_c).
      for (int c = 0; c < num_free; ++c) {
        for (int d = c; d < num_free; ++d) {
          const double trace = trace_of_product(md[c], md[d]);
          pass.helmert(c, d) += trace;
          if (d != c) pass.helmert(d, c) += trace;
        }
      }
    }
  });
  Pass pass = zero;
  for (const Pass& chunk_pass : chunk_passes) {
    pass.weighted_sum += chunk_pass.weighted_sum;
    pass.redundancy_part += chunk_pass.redundancy_part;
    pass.helmert += chunk_pass.helmert;
    pass.chi_square += chunk_pass.chi_square;
  }
  return pass;
}

// Covariance of the multipliers (2 H^-1) and each one's relative standard
// deviation: against the largest multiplier of its group's parameters (its
// own for a parameter that is all of its group). A shape component (constant
// / proportional part, across / along the motion) determined to lie far
// below its group's level is determined, not inseparable; a group whose
// level is not determined is tied to another group, as without shape
// components.
struct MultiplierUncertainty {
  Eigen::MatrixXd covariance;
  Eigen::VectorXd relative;
  int worst = 0;  // the least determined parameter that is not held
  double worst_relative = 0.0;
};

NoiseGroup GroupOfParameter(const std::vector<int>& parameter) {
  return GroupOf(static_cast<NoiseComponent>(parameter.front()));
}

bool SharesItsGroup(const std::vector<std::vector<int>>& parameters, int p) {
  for (size_t q = 0; q < parameters.size(); ++q) {
    if (static_cast<int>(q) != p &&
        GroupOfParameter(parameters[q]) == GroupOfParameter(parameters[p])) {
      return true;
    }
  }
  return false;
}

MultiplierUncertainty Uncertainty(
    const Pass& pass,
    const Eigen::VectorXd& mu,
    const std::vector<std::vector<int>>& parameters,
    const std::vector<bool>& held) {
  const int n = static_cast<int>(mu.size());
  std::vector<int> free;
  for (int p = 0; p < n; ++p) {
    if (!held[p]) free.push_back(p);
  }
  MultiplierUncertainty u;
  u.covariance = Eigen::MatrixXd::Zero(n, n);
  if (!free.empty()) {
    const Eigen::MatrixXd helmert = pass.helmert(free, free);
    const Eigen::MatrixXd inverse =
        helmert.completeOrthogonalDecomposition().pseudoInverse();
    u.covariance(free, free) = 2.0 * inverse;
  }
  u.relative = Eigen::VectorXd::Zero(n);
  u.worst = -1;
  for (const int p : free) {
    double reference = mu(p);
    for (int q = 0; q < n; ++q) {
      if (GroupOfParameter(parameters[q]) == GroupOfParameter(parameters[p])) {
        reference = std::max(reference, mu(q));
      }
    }
    u.relative(p) = std::sqrt(std::max(0.0, u.covariance(p, p))) / reference;
    if (!std::isfinite(u.relative(p))) u.relative(p) = 1e300;
    if (u.worst < 0 || u.relative(p) > u.relative(u.worst)) u.worst = p;
  }
  // A parameter held at the floor: the data put it below the floor, which
  // its own information (the diagonal, the others fixed) bounds.
  for (int p = 0; p < n; ++p) {
    if (!held[p]) continue;
    const double information = pass.helmert(p, p);
    u.covariance(p, p) = information > 0.0 ? 2.0 / information : 0.0;
    u.relative(p) = std::sqrt(u.covariance(p, p)) / std::max(mu(p), 1.0);
  }
  u.worst_relative = u.worst < 0 ? 0.0 : u.relative(u.worst);
  if (u.worst < 0) u.worst = 0;
  return u;
}

}  // namespace

double NoiseEstimate::SigmaRatio(NoiseGroup group) const {
  return std::sqrt(variance_factors[Index(group)]);
}

double NoiseEstimate::SigmaRatio(NoiseComponent component) const {
  return std::sqrt(component_factors[Index(component)]);
}

MotionPairs ScaleCovariances(const MotionPairs& pairs,
                             const NoiseEstimate& estimate) {
  return ScaleCovariances(pairs, CovarianceFactors(estimate.component_factors));
}

NoiseEstimate EstimateNoise(const MotionPairs& pairs,
                            const std::vector<int>& used,
                            const Rigid3d& odom_from_cam,
                            const std::vector<double>& metric_scales,
                            const CalibrationOptions& options,
                            bool estimate_z,
                            const ComponentFactors& start,
                            const ComponentFactors& initial_guess) {
  NoiseEstimate estimate;
  estimate.component_factors = start;
  estimate.noise = ScaleNoiseComponents(options.noise, start);
  estimate.num_pairs = static_cast<int>(used.size());
  if (used.empty()) return estimate;
  const NoiseModel start_noise = estimate.noise;
  const NoiseFactors start_covariance = CovarianceFactors(start);

  // Parameter columns: rotation, translation, then one scale per segment.
  std::map<int, int> scale_columns;
  const int first_scale_column = estimate_z ? 6 : 5;
  for (const int i : used) {
    scale_columns.emplace(pairs[i].segment, 0);
  }
  int num_columns = first_scale_column;
  for (auto& [segment, column] : scale_columns) column = num_columns++;

  const int num_used = static_cast<int>(used.size());
  std::vector<PairTerms> terms(used.size());
  // The components' traces, per chunk of pairs (parallel_chunks.h).
  struct Traces {
    std::array<double, kNumNoiseComponents> component = {};
    std::array<double, kNumCoupled> coupled = {};
  };
  std::vector<Traces> chunk_traces(NumChunks(num_used));
  ForEachChunk(
      num_used, options.num_threads, [&](int chunk, int begin, int end) {
        Traces& traces = chunk_traces[chunk];
        // A pair's parts are gathered here and copied at their exact count:
        // grown by push_back, each pair's vector would hold room for 16 (2 KiB
        // unused).
        std::vector<CovariancePart> parts;
        parts.reserve(kNumNoiseComponents + kNumCoupled);
        for (int k = begin; k < end; ++k) {
          // Only a pair with its own covariances is copied to scale them
          // (a copy carries the pair's odometry samples too).
          const MotionPair& given = pairs[used[k]];
          std::optional<MotionPair> scaled;
          if (given.odom_covariance || given.cam_covariance) {
            scaled = ScaleCovariancesOfPair(given, start_covariance);
          }
          const MotionPair& pair = scaled ? *scaled : given;
          const double scale = metric_scales.at(pair.segment);
          const ResidualNoiseJacobians jacobians =
              HandEyeResidualNoiseJacobians(pair, odom_from_cam, scale);
          PairTerms& term = terms[k];
          parts.clear();
          term.residual = HandEyeResidual(pair, odom_from_cam, scale);
          term.jacobian = ResidualJacobian(pair,
                                           odom_from_cam,
                                           scale,
                                           scale_columns.at(pair.segment),
                                           num_columns,
                                           estimate_z);
          const StepSize step =
              ModelledStep(pair, odom_from_cam, scale, start_noise);
          std::array<Matrix6d, kNumNoiseComponents> contributions;
          for (int c = 0; c < kNumNoiseComponents; ++c) {
            contributions[c] =
                Contribution(pair, jacobians, start_noise, step, {c});
            traces.component[c] += contributions[c].trace();
            if (!contributions[c].isZero(0.0)) {
              parts.push_back({c, c, contributions[c]});
            }
          }
          for (int q = 0; q < kNumCoupled; ++q) {
            const int a = Index(kCoupled[q].first),
                      b = Index(kCoupled[q].second);
            if (contributions[a].isZero(0.0) || contributions[b].isZero(0.0)) {
              continue;
            }
            const Matrix6d coupled =
                Contribution(pair, jacobians, start_noise, step, {a, b}) -
                contributions[a] - contributions[b];
            traces.coupled[q] += coupled.trace();
            if (!coupled.isZero(0.0)) parts.push_back({a, b, coupled});
          }
          term.parts.assign(parts.begin(), parts.end());
          term.interpolation = InterpolationContribution(
              pair, odom_from_cam, scale, options.noise);
        }
      });
  std::array<double, kNumNoiseComponents> trace = {};
  std::array<double, kNumCoupled> coupled_trace = {};
  for (const Traces& traces : chunk_traces) {
    for (int c = 0; c < kNumNoiseComponents; ++c) {
      trace[c] += traces.component[c];
    }
    for (int q = 0; q < kNumCoupled; ++q) coupled_trace[q] += traces.coupled[q];
  }
  double total_trace = 0.0;
  for (const double t : trace) total_trace += t;

  // Components the data contain start as parameters of their own; the others
  // (zero noise given, e.g. no odometry tilt noise; no own covariances) are
  // fixed.
  std::vector<std::vector<int>> parameters;
  for (int c = 0; c < kNumNoiseComponents; ++c) {
    estimate.component_present[c] = trace[c] > 1e-12 * total_trace;
    if (!estimate.component_present[c]) continue;
    // The odometry's tilt noise states how planar the motion is assumed to
    // be; the planarity check tests that against the residuals. Estimated,
    // it would absorb a tilted floor as noise and leave nothing to test.
    if (c == Index(NoiseComponent::kOdometryTilt)) continue;
    parameters.push_back({c});
  }

  Eigen::VectorXd mu;
  Pass data_pass;  // the pairs' sums alone
  Pass pass;       // with the prior: the scoring's
  const auto evaluate = [&](const ParameterOf& parameter_of) {
    data_pass = Evaluate(terms, parameter_of, mu, options.num_threads);
    pass = WithPrior(data_pass, mu, options.noise_prior_weight);
  };
  std::array<double, kNumNoiseComponents> last_multiplier;
  for (int c = 0; c < kNumNoiseComponents; ++c) {
    last_multiplier[c] =
        std::clamp(initial_guess[c] / start[c], kMinMultiplier, kMaxMultiplier);
  }
  while (!parameters.empty()) {
    const int num_free = static_cast<int>(parameters.size());
    ParameterOf parameter_of;
    parameter_of.fill(num_free);
    for (int p = 0; p < num_free; ++p) {
      for (const int c : parameters[p]) parameter_of[c] = p;
    }
    // Warm start: a tie starts from its first member's last multiplier.
    mu.resize(num_free);
    for (int p = 0; p < num_free; ++p) {
      mu(p) = last_multiplier[parameters[p].front()];
    }
    int iteration = 0;
    bool converged = false;
    std::vector<bool> held(num_free, false);
    for (; iteration < kMaxIterations; ++iteration) {
      evaluate(parameter_of);
      const Eigen::VectorXd score = pass.weighted_sum - pass.redundancy_part;
      // Active set: a parameter at the floor whose score points below it
      // (the data ask for a smaller, even negative, variance) is held there
      // and left out of the step. Stepping it anyway would push the others
      // to compensate (on exact data: one component x1000, the rest at the
      // floor) and decide the ties on a near-singular H.
      std::vector<int> free;
      for (int p = 0; p < num_free; ++p) {
        held[p] = mu(p) <= kMinMultiplier && score(p) <= 0.0;
        if (!held[p]) free.push_back(p);
      }
      // A parameter the data cannot separate makes the iteration creep
      // along a ridge: tie it as soon as that shows, not after 100 steps.
      if (iteration >= kIterationsBeforeTieCheck &&
          Uncertainty(data_pass, mu, parameters, held).worst_relative >
              kMaxRelativeStddev) {
        break;
      }
      if (free.empty()) {
        converged = true;
        break;
      }
      // Fisher scoring (Helmert's step where Cov is linear in mu) converges
      // in a few iterations; where it fails, Foerstner's multiplicative step.
      // With a prior, also where it would move a multiplier by more than
      // kMaxFisherRatio, for all: the prior's 1 / mu^2 is far from linear
      // near the floor, where the linearised step overshoots from the floor
      // to the start and back.
      const Eigen::MatrixXd helmert = pass.helmert(free, free);
      const Eigen::VectorXd step =
          helmert.completeOrthogonalDecomposition().solve(
              Eigen::VectorXd(score(free)));
      bool fisher = true;
      for (size_t k = 0; k < free.size(); ++k) {
        const double ratio = (mu(free[k]) + step(k)) / mu(free[k]);
        const bool far = ratio > kMaxFisherRatio ||
                         (ratio > 0.0 && ratio < 1.0 / kMaxFisherRatio);
        if (!std::isfinite(ratio) ||
            (options.noise_prior_weight > 0.0 && far)) {
          fisher = false;
        }
      }
      double change = 0.0;
      for (size_t k = 0; k < free.size(); ++k) {
        const int p = free[k];
        double next = mu(p) + step(k);
        if (!fisher) {
          next = pass.redundancy_part(p) > 0.0
                     ? mu(p) * pass.weighted_sum(p) / pass.redundancy_part(p)
                     : mu(p);
        }
        if (!std::isfinite(next)) next = mu(p);
        next = std::clamp(next, kMinMultiplier, kMaxMultiplier);
        change = std::max(change, std::abs(next / mu(p) - 1.0));
        mu(p) = next;
      }
      if (change < kConvergence) {
        converged = true;
        break;
      }
    }
    estimate.num_iterations += iteration + 1;
    if (converged || iteration == kMaxIterations) {
      evaluate(parameter_of);
      const Eigen::VectorXd score = pass.weighted_sum - pass.redundancy_part;
      for (int p = 0; p < num_free; ++p) {
        held[p] = mu(p) <= kMinMultiplier && score(p) <= 0.0;
      }
    }
    for (int p = 0; p < num_free; ++p) {
      for (const int c : parameters[p]) last_multiplier[c] = mu(p);
    }
    const MultiplierUncertainty uncertainty =
        Uncertainty(data_pass, mu, parameters, held);
    // What the pairs determine decides the ties (the prior would determine
    // every level); the estimate's own uncertainty includes the prior.
    const Eigen::MatrixXd& covariance = uncertainty.covariance;
    const Eigen::MatrixXd posterior_covariance =
        options.noise_prior_weight > 0.0
            ? Uncertainty(pass, mu, parameters, held).covariance
            : covariance;
    const Eigen::VectorXd& relative = uncertainty.relative;
    const int worst = uncertainty.worst;
    if (uncertainty.worst_relative <= kMaxRelativeStddev) {
      // A level at the ceiling is a finding, not an estimate: kept at the
      // start, the others estimated again without it. One at the floor is
      // held there (the pairs fit better than the given noise allows) and
      // reported.
      bool any_at_ceiling = false;
      for (int p = num_free - 1; p >= 0; --p) {
        if (mu(p) <= kMinMultiplier * (1.0 + kAtBound)) {
          for (const int c : parameters[p]) {
            estimate.component_bound[c] = NoiseBound::kFloor;
          }
        } else if (mu(p) >= kMaxMultiplier * (1.0 - kAtBound)) {
          for (const int c : parameters[p]) {
            estimate.component_bound[c] = NoiseBound::kCeiling;
          }
          parameters.erase(parameters.begin() + p);
          any_at_ceiling = true;
        }
      }
      if (any_at_ceiling) {
        // Floors are decided again with the ceiling's level kept.
        for (NoiseBound& bound : estimate.component_bound) {
          if (bound == NoiseBound::kFloor) bound = NoiseBound::kNone;
        }
        continue;
      }
      // In the refinement's columns, which hold z (WidenForEstimatedNoise).
      if (!estimate_z) {
        estimate.kenward_roger_term = KenwardRogerTerm(
            terms, parameter_of, mu, posterior_covariance, options.num_threads);
        for (const auto& [segment, column] : scale_columns) {
          estimate.kenward_roger_segments.push_back(segment);
        }
      }
      for (int p = 0; p < num_free; ++p) {
        const int representative =
            *std::min_element(parameters[p].begin(), parameters[p].end());
        for (const int c : parameters[p]) {
          estimate.component_factors[c] = start[c] * mu(p);
          estimate.component_estimated[c] = true;
          estimate.component_tie[c] = representative;
          estimate.component_relative_stddev[c] = relative(p);
          const int g = Index(GroupOf(static_cast<NoiseComponent>(c)));
          estimate.redundancy[g] +=
              mu(p) * data_pass.redundancy_part(p) / parameters[p].size();
          estimate.factor_relative_stddev[g] =
              std::max(estimate.factor_relative_stddev[g], relative(p));
        }
      }
      break;
    }
    if (num_free == 1) {
      // Not determined even with every component tied: keep the given noise.
      parameters.clear();
      break;
    }
    // Tie the worst parameter to the one its estimate trades off with most
    // (most negative correlation), within its group where it can: the
    // group's given shape is the natural fallback.
    const auto group_of = [&](int p) {
      return GroupOfParameter(parameters[p]);
    };
    const bool same_group_exists = SharesItsGroup(parameters, worst);
    // A parameter held at the floor is determined; tie to one that is not,
    // where there is one.
    bool free_partner_exists = false;
    for (int p = 0; p < num_free; ++p) {
      if (p != worst && !held[p] &&
          (!same_group_exists || group_of(p) == group_of(worst))) {
        free_partner_exists = true;
      }
    }
    int partner = worst == 0 ? 1 : 0;
    double most_negative = 2.0;
    for (int p = 0; p < num_free; ++p) {
      if (p == worst) continue;
      if (same_group_exists && group_of(p) != group_of(worst)) continue;
      if (free_partner_exists && held[p]) continue;
      const double correlation =
          covariance(worst, p) /
          std::sqrt(
              std::max(1e-300, covariance(worst, worst) * covariance(p, p)));
      if (correlation < most_negative) {
        most_negative = correlation;
        partner = p;
      }
    }
    parameters[partner].insert(parameters[partner].end(),
                               parameters[worst].begin(),
                               parameters[worst].end());
    parameters.erase(parameters.begin() + worst);
  }
  estimate.noise =
      ScaleNoiseComponents(options.noise, estimate.component_factors);

  // A level kept at the ceiling leaves the fit's chi-square above its
  // redundancy (a noise the model cannot take up): the covariance is widened.
  const bool any_at_ceiling =
      std::any_of(estimate.component_bound.begin(),
                  estimate.component_bound.end(),
                  [](NoiseBound b) { return b == NoiseBound::kCeiling; });
  if (any_at_ceiling) {
    double chi_square = data_pass.chi_square;
    if (parameters.empty()) {
      ParameterOf all_fixed;
      all_fixed.fill(0);
      const Eigen::VectorXd start_multiplier = Eigen::VectorXd::Ones(1);
      chi_square = 0.0;
      for (const PairTerms& term : terms) {
        const Matrix6d covariance =
            PairCovariance(term, all_fixed, start_multiplier, nullptr);
        chi_square += term.residual.dot(covariance.ldlt().solve(term.residual));
      }
    }
    const double redundancy =
        6.0 * static_cast<double>(terms.size()) - num_columns;
    if (redundancy > 0.0 && chi_square > redundancy) {
      estimate.misfit_widening = std::sqrt(chi_square / redundancy);
    }
  }

  // Per group: the level (estimated over given contribution) and the ties.
  std::array<double, kNumNoiseGroups> given = {}, estimated = {};
  for (int c = 0; c < kNumNoiseComponents; ++c) {
    const int g = Index(GroupOf(static_cast<NoiseComponent>(c)));
    const double base = trace[c] / start[c];
    given[g] += base;
    estimated[g] += base * estimate.component_factors[c];
    if (estimate.component_estimated[c]) estimate.estimated[g] = true;
  }
  for (int k = 0; k < kNumCoupled; ++k) {
    const int a = Index(kCoupled[k].first), b = Index(kCoupled[k].second);
    const int g = Index(GroupOf(kCoupled[k].first));
    if (g != Index(GroupOf(kCoupled[k].second))) continue;
    const double base = coupled_trace[k] / std::sqrt(start[a] * start[b]);
    given[g] += base;
    estimated[g] += base * std::sqrt(estimate.component_factors[a] *
                                     estimate.component_factors[b]);
  }
  for (int g = 0; g < kNumNoiseGroups; ++g) {
    estimate.variance_factors[g] =
        given[g] > 0.0 ? estimated[g] / given[g] : 1.0;
  }
  // Groups with components in one tie share a tie index (the smallest).
  for (bool changed = true; changed;) {
    changed = false;
    for (int c = 0; c < kNumNoiseComponents; ++c) {
      for (int d = 0; d < kNumNoiseComponents; ++d) {
        if (!estimate.component_estimated[c] ||
            !estimate.component_estimated[d] ||
            estimate.component_tie[c] != estimate.component_tie[d]) {
          continue;
        }
        const int g = Index(GroupOf(static_cast<NoiseComponent>(c)));
        const int h = Index(GroupOf(static_cast<NoiseComponent>(d)));
        if (estimate.tie[h] > estimate.tie[g]) {
          estimate.tie[h] = estimate.tie[g];
          changed = true;
        }
      }
    }
  }
  return estimate;
}

}  // namespace odomcal
