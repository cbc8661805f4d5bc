// Variance-component estimation, see noise_estimation.h. The groups are
// worked on as "components": a component is a set of tied groups with one
// multiplier on the sum of their contributions (at the starting factors);
// groups that are kept at the given noise form the fixed part.

#include "odomcal/solver/noise_estimation.h"

#include "odomcal/solver/hand_eye_residual.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

namespace odomcal {
namespace {

using Matrix6X = Eigen::Matrix<double, 6, Eigen::Dynamic>;

constexpr int kMaxIterations = 100;
constexpr double kConvergence = 1e-5;
// The given noise is a prior, not only a start: an estimate at most 10x below
// it (in standard deviation). Exact or over-fitted data (simulations, a
// handful of pairs) would otherwise claim a near-zero noise, a covariance of
// zero and a gate that rejects every pair off by rounding.
constexpr double kMinMultiplier = 0.01;
constexpr double kMaxMultiplier = 1e6;

int Index(NoiseGroup group) { return static_cast<int>(group); }

// Keeps only the rows and columns of `block` (0: rotation, 1: translation).
MotionCovariance OnlyBlock(const MotionCovariance& covariance, int block) {
  MotionCovariance masked = MotionCovariance::Zero();
  masked.block<3, 3>(3 * block, 3 * block) =
      covariance.block<3, 3>(3 * block, 3 * block);
  return masked;
}

// Contribution of each group to Cov(r) of one pair.
std::array<Matrix6d, kNumNoiseGroups> GroupContributions(
    const MotionPair& pair,
    const Rigid3d& odom_from_cam,
    double scale,
    const NoiseModel& noise) {
  // The odometry's interpolation error is measured from the data, not a
  // noise level: it belongs to no group (InterpolationContribution).
  MotionPair without_interpolation = pair;
  without_interpolation.odom_interpolation_covariance.reset();
  const MotionCovariance odom =
      OdometryCovariance(without_interpolation, noise);
  const MotionCovariance cam = CameraCovariance(pair, noise);
  std::array<Matrix6d, kNumNoiseGroups> contributions;
  for (int g = 0; g < kNumNoiseGroups; ++g) {
    MotionPair masked = without_interpolation;
    const bool is_odometry = g < 2;
    masked.odom_covariance =
        is_odometry ? OnlyBlock(odom, g % 2) : MotionCovariance::Zero();
    masked.cam_covariance =
        is_odometry ? MotionCovariance::Zero() : OnlyBlock(cam, g % 2);
    contributions[g] =
        HandEyeResidualCovariance(masked, odom_from_cam, scale, noise);
  }
  return contributions;
}

// Contribution of the odometry's interpolation error to Cov(r), which no
// noise factor scales (zero for pairs without one).
Matrix6d InterpolationContribution(const MotionPair& pair,
                                   const Rigid3d& odom_from_cam,
                                   double scale,
                                   const NoiseModel& noise) {
  if (!pair.odom_interpolation_covariance) return Matrix6d::Zero();
  MotionPair only = pair;
  only.odom_covariance = MotionCovariance::Zero();
  only.cam_covariance = MotionCovariance::Zero();
  return HandEyeResidualCovariance(only, odom_from_cam, scale, noise);
}

// d r / d [phi(3), p_x, p_y, (p_z), s_k...] by central differences.
Matrix6X ResidualJacobian(const MotionPair& pair,
                          const Rigid3d& odom_from_cam,
                          double scale,
                          int scale_column,
                          int num_columns,
                          bool estimate_z) {
  Matrix6X jacobian = Matrix6X::Zero(6, num_columns);
  constexpr double kStep = 1e-6;
  for (int k = 0; k < 3; ++k) {
    Rigid3d plus = odom_from_cam, minus = odom_from_cam;
    plus.rotation =
        ExpRotation(Eigen::Vector3d::Unit(k) * kStep) * odom_from_cam.rotation;
    minus.rotation =
        ExpRotation(-Eigen::Vector3d::Unit(k) * kStep) * odom_from_cam.rotation;
    jacobian.col(k) = (HandEyeResidual(pair, plus, scale) -
                       HandEyeResidual(pair, minus, scale)) /
                      (2.0 * kStep);
  }
  const int num_translations = estimate_z ? 3 : 2;
  for (int k = 0; k < num_translations; ++k) {
    Rigid3d plus = odom_from_cam, minus = odom_from_cam;
    plus.translation(k) += kStep;
    minus.translation(k) -= kStep;
    jacobian.col(3 + k) = (HandEyeResidual(pair, plus, scale) -
                           HandEyeResidual(pair, minus, scale)) /
                          (2.0 * kStep);
  }
  const double h = kStep * std::max(1.0, std::abs(scale));
  jacobian.col(scale_column) =
      (HandEyeResidual(pair, odom_from_cam, scale + h) -
       HandEyeResidual(pair, odom_from_cam, scale - h)) /
      (2.0 * h);
  return jacobian;
}

struct PairTerms {
  Vector6d residual;
  Matrix6X jacobian;
  std::array<Matrix6d, kNumNoiseGroups> contributions;
  Matrix6d interpolation;  // unscaled
};

// Sums of one pass over the pairs at the given component multipliers.
struct Pass {
  Eigen::VectorXd weighted_sum;     // q_c = sum e^T P V_c P e
  Eigen::VectorXd redundancy_part;  // t_c = sum tr(V_c M)
  Eigen::MatrixXd helmert;          // H_cd = sum tr(M V_c M V_d)
};

Pass Evaluate(const std::vector<PairTerms>& terms,
              const std::vector<std::vector<int>>& components,
              const std::vector<int>& fixed,
              const NoiseFactors& start,
              const Eigen::VectorXd& multipliers) {
  const int num_components = static_cast<int>(components.size());
  std::vector<std::vector<Matrix6d>> bases(terms.size());
  std::vector<Matrix6d> precisions(terms.size());
  const int num_columns = static_cast<int>(terms.front().jacobian.cols());
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(num_columns, num_columns);
  for (size_t i = 0; i < terms.size(); ++i) {
    Matrix6d covariance = terms[i].interpolation;
    for (const int g : fixed) {
      covariance += start[g] * terms[i].contributions[g];
    }
    for (int c = 0; c < num_components; ++c) {
      Matrix6d base = Matrix6d::Zero();
      for (const int g : components[c]) {
        base += start[g] * terms[i].contributions[g];
      }
      bases[i].push_back(base);
      covariance += multipliers(c) * base;
    }
    covariance.diagonal().array() += 1e-12 * covariance.trace() + 1e-300;
    precisions[i] = covariance.ldlt().solve(Matrix6d::Identity());
    normal += terms[i].jacobian.transpose() * precisions[i] * terms[i].jacobian;
  }
  const Eigen::MatrixXd normal_inverse =
      normal.completeOrthogonalDecomposition().pseudoInverse();
  Pass pass;
  pass.weighted_sum = Eigen::VectorXd::Zero(num_components);
  pass.redundancy_part = Eigen::VectorXd::Zero(num_components);
  pass.helmert = Eigen::MatrixXd::Zero(num_components, num_components);
  for (size_t i = 0; i < terms.size(); ++i) {
    const Matrix6d& p = precisions[i];
    const Matrix6X pj = p * terms[i].jacobian;
    const Matrix6d m = p - pj * normal_inverse * pj.transpose();
    const Vector6d pe = p * terms[i].residual;
    std::vector<Matrix6d> mv;
    for (int c = 0; c < num_components; ++c) {
      pass.weighted_sum(c) += pe.dot(bases[i][c] * pe);
      pass.redundancy_part(c) += (bases[i][c] * m).trace();
      mv.push_back(m * bases[i][c]);
    }
    for (int c = 0; c < num_components; ++c) {
      for (int d = 0; d < num_components; ++d) {
        pass.helmert(c, d) += (mv[c] * mv[d]).trace();
      }
    }
  }
  return pass;
}

std::string Ratio(double value) {
  std::ostringstream text;
  text.precision(2);
  text << value;
  return text.str();
}

}  // namespace

std::string ToString(NoiseGroup group) {
  switch (group) {
    case NoiseGroup::kOdometryRotation:
      return "odometry rotation";
    case NoiseGroup::kOdometryTranslation:
      return "odometry translation";
    case NoiseGroup::kCameraRotation:
      return "camera rotation";
    case NoiseGroup::kCameraTranslation:
      return "camera translation";
  }
  return "unknown";
}

double NoiseEstimate::SigmaRatio(NoiseGroup group) const {
  return std::sqrt(variance_factors[Index(group)]);
}

NoiseModel ScaleNoise(const NoiseModel& noise, const NoiseFactors& factors) {
  const double odom_rotation =
      std::sqrt(factors[Index(NoiseGroup::kOdometryRotation)]);
  const double odom_translation =
      std::sqrt(factors[Index(NoiseGroup::kOdometryTranslation)]);
  NoiseModel scaled = noise;
  scaled.odom_yaw_sigma_deg *= odom_rotation;
  scaled.odom_yaw_sigma_rel *= odom_rotation;
  scaled.odom_tilt_sigma_deg *= odom_rotation;
  scaled.odom_translation_sigma_m *= odom_translation;
  scaled.odom_translation_sigma_rel *= odom_translation;
  scaled.cam_rotation_sigma_deg *=
      std::sqrt(factors[Index(NoiseGroup::kCameraRotation)]);
  scaled.cam_translation_sigma_rel *=
      std::sqrt(factors[Index(NoiseGroup::kCameraTranslation)]);
  return scaled;
}

MotionPairs ScaleCovariances(const MotionPairs& pairs,
                             const NoiseFactors& factors) {
  auto scale =
      [](MotionCovariance* covariance, double rotation, double translation) {
        Vector6d sigma;
        sigma << Eigen::Vector3d::Constant(std::sqrt(rotation)),
            Eigen::Vector3d::Constant(std::sqrt(translation));
        *covariance = sigma.asDiagonal() * *covariance * sigma.asDiagonal();
      };
  MotionPairs scaled = pairs;
  for (MotionPair& pair : scaled) {
    if (pair.odom_covariance) {
      scale(&*pair.odom_covariance,
            factors[Index(NoiseGroup::kOdometryRotation)],
            factors[Index(NoiseGroup::kOdometryTranslation)]);
    }
    if (pair.cam_covariance) {
      scale(&*pair.cam_covariance,
            factors[Index(NoiseGroup::kCameraRotation)],
            factors[Index(NoiseGroup::kCameraTranslation)]);
    }
  }
  return scaled;
}

NoiseEstimate EstimateNoise(const MotionPairs& pairs,
                            const std::vector<int>& used,
                            const Rigid3d& odom_from_cam,
                            const std::vector<double>& metric_scales,
                            const CalibrationOptions& options,
                            bool estimate_z,
                            const NoiseFactors& start) {
  NoiseEstimate estimate;
  estimate.variance_factors = start;
  estimate.noise = ScaleNoise(options.noise, start);
  estimate.num_pairs = static_cast<int>(used.size());
  if (used.empty()) return estimate;

  // Parameter columns: rotation, translation, then one scale per segment.
  std::map<int, int> scale_columns;
  const int first_scale_column = estimate_z ? 6 : 5;
  for (const int i : used) {
    scale_columns.emplace(pairs[i].segment, 0);
  }
  int num_columns = first_scale_column;
  for (auto& [segment, column] : scale_columns) column = num_columns++;

  std::vector<PairTerms> terms;
  std::array<double, kNumNoiseGroups> group_trace = {0.0, 0.0, 0.0, 0.0};
  for (const int i : used) {
    const MotionPair& pair = pairs[i];
    const double scale = metric_scales.at(pair.segment);
    PairTerms term;
    term.residual = HandEyeResidual(pair, odom_from_cam, scale);
    term.jacobian = ResidualJacobian(pair,
                                     odom_from_cam,
                                     scale,
                                     scale_columns.at(pair.segment),
                                     num_columns,
                                     estimate_z);
    term.contributions =
        GroupContributions(pair, odom_from_cam, scale, options.noise);
    term.interpolation =
        InterpolationContribution(pair, odom_from_cam, scale, options.noise);
    for (int g = 0; g < kNumNoiseGroups; ++g) {
      group_trace[g] += term.contributions[g].trace();
    }
    terms.push_back(std::move(term));
  }
  double total_trace = 0.0;
  for (const double trace : group_trace) total_trace += trace;

  // Groups that contribute start as components of their own; the others
  // (zero noise given, e.g. no odometry tilt noise) are fixed.
  std::vector<std::vector<int>> components;
  std::vector<int> fixed;
  for (int g = 0; g < kNumNoiseGroups; ++g) {
    if (group_trace[g] > 1e-12 * total_trace) {
      components.push_back({g});
    } else {
      fixed.push_back(g);
    }
  }

  Eigen::VectorXd multipliers;
  Pass pass;
  while (!components.empty()) {
    const int num_components = static_cast<int>(components.size());
    multipliers = Eigen::VectorXd::Ones(num_components);
    int iteration = 0;
    for (; iteration < kMaxIterations; ++iteration) {
      pass = Evaluate(terms, components, fixed, start, multipliers);
      // Helmert's step (E[q] = H mu at the solution) converges in a few
      // iterations; where it leaves the positive range, Foerstner's
      // multiplicative step, which stays positive.
      const Eigen::VectorXd helmert =
          pass.helmert.completeOrthogonalDecomposition().solve(
              pass.weighted_sum);
      const bool helmert_positive =
          helmert.allFinite() && (helmert.array() > 0.0).all();
      double change = 0.0;
      for (int c = 0; c < num_components; ++c) {
        double next = multipliers(c);
        if (helmert_positive) {
          next = helmert(c);
        } else if (pass.redundancy_part(c) > 0.0) {
          next =
              multipliers(c) * pass.weighted_sum(c) / pass.redundancy_part(c);
        }
        next = std::clamp(next, kMinMultiplier, kMaxMultiplier);
        change = std::max(change, std::abs(next / multipliers(c) - 1.0));
        multipliers(c) = next;
      }
      if (change < kConvergence) break;
    }
    estimate.num_iterations += iteration + 1;
    pass = Evaluate(terms, components, fixed, start, multipliers);

    // Relative standard deviation of each multiplier: Cov = 2 H^-1.
    const Eigen::MatrixXd covariance =
        2.0 * pass.helmert.completeOrthogonalDecomposition().pseudoInverse();
    int worst = 0;
    Eigen::VectorXd relative(num_components);
    for (int c = 0; c < num_components; ++c) {
      relative(c) = std::sqrt(std::max(0.0, covariance(c, c))) / multipliers(c);
      if (!std::isfinite(relative(c))) relative(c) = 1e300;
      if (relative(c) > relative(worst)) worst = c;
    }
    if (relative(worst) <= kMaxRelativeStddev) {
      for (int c = 0; c < num_components; ++c) {
        const int representative =
            *std::min_element(components[c].begin(), components[c].end());
        for (const int g : components[c]) {
          estimate.variance_factors[g] = start[g] * multipliers(c);
          estimate.estimated[g] = true;
          estimate.tie[g] = representative;
          estimate.redundancy[g] =
              multipliers(c) * pass.redundancy_part(c) / components[c].size();
          estimate.factor_relative_stddev[g] = relative(c);
        }
      }
      break;
    }
    if (num_components == 1) {
      // Not determined even with every group tied: keep the given noise.
      for (const int g : components[0]) fixed.push_back(g);
      components.clear();
      break;
    }
    // Tie the worst component to the one its estimate trades off with most
    // (most negative correlation).
    int partner = worst == 0 ? 1 : 0;
    double most_negative = 2.0;
    for (int c = 0; c < num_components; ++c) {
      if (c == worst) continue;
      const double correlation =
          covariance(worst, c) /
          std::sqrt(
              std::max(1e-300, covariance(worst, worst) * covariance(c, c)));
      if (correlation < most_negative) {
        most_negative = correlation;
        partner = c;
      }
    }
    components[partner].insert(components[partner].end(),
                               components[worst].begin(),
                               components[worst].end());
    components.erase(components.begin() + worst);
  }
  estimate.noise = ScaleNoise(options.noise, estimate.variance_factors);
  return estimate;
}

std::string NoiseSummary(const NoiseEstimate& estimate) {
  std::ostringstream text;
  text << "noise estimated from " << estimate.num_pairs
       << " pairs (standard deviations relative to the given noise): ";
  bool first = true;
  std::vector<std::string> kept;
  for (int g = 0; g < kNumNoiseGroups; ++g) {
    if (!estimate.estimated[g]) {
      kept.push_back(ToString(static_cast<NoiseGroup>(g)));
      continue;
    }
    if (estimate.tie[g] != g) continue;  // listed with its representative
    std::vector<std::string> members;
    for (int h = 0; h < kNumNoiseGroups; ++h) {
      if (estimate.estimated[h] && estimate.tie[h] == g) {
        members.push_back(ToString(static_cast<NoiseGroup>(h)));
      }
    }
    text << (first ? "" : ", ") << members[0];
    for (size_t k = 1; k < members.size(); ++k) {
      text << (k + 1 == members.size() ? " and " : ", ") << members[k];
    }
    if (members.size() > 1) text << " (tied: not separable)";
    text << " x" << Ratio(estimate.SigmaRatio(static_cast<NoiseGroup>(g)));
    first = false;
  }
  if (first) text << "none determined";
  if (!kept.empty()) {
    text << "; kept as given: ";
    for (size_t k = 0; k < kept.size(); ++k) {
      text << (k == 0 ? "" : ", ") << kept[k];
    }
    text << " (zero or not determined by these pairs)";
  }
  return text.str();
}

}  // namespace odomcal
