// Variance-component estimation, see noise_estimation.h. The components are
// worked on as "parameters": a parameter is a set of tied components with
// one multiplier on their standard deviations' squares (relative to the
// starting factors); components that are kept at the given noise form the
// fixed parameter, whose multiplier stays 1.

#include "odomcal/solver/noise_estimation.h"

#include "odomcal/solver/hand_eye_residual.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <map>
#include <optional>
#include <sstream>
#include <utility>

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
// Fisher steps before an unseparable parameter is tied without converging.
constexpr int kIterationsBeforeTieCheck = 3;

int Index(NoiseGroup group) { return static_cast<int>(group); }
int Index(NoiseComponent component) { return static_cast<int>(component); }

// Components whose standard deviations add (a constant and a proportional
// part; the rotation and translation blocks of an own covariance, whose
// cross block scales with both): Cov has a term sqrt(mu_a mu_b) X_ab.
constexpr std::pair<NoiseComponent, NoiseComponent> kCoupled[] = {
    {NoiseComponent::kOdometryYawConstant,
     NoiseComponent::kOdometryYawProportional},
    {NoiseComponent::kOdometryTranslationConstant,
     NoiseComponent::kOdometryTranslationProportional},
    {NoiseComponent::kOdometryRotationCovariance,
     NoiseComponent::kOdometryTranslationCovariance},
    {NoiseComponent::kCameraRotationCovariance,
     NoiseComponent::kCameraTranslationCovariance},
};
constexpr int kNumCoupled = 4;

bool IsOdometry(int component) {
  return GroupOf(static_cast<NoiseComponent>(component)) ==
             NoiseGroup::kOdometryRotation ||
         GroupOf(static_cast<NoiseComponent>(component)) ==
             NoiseGroup::kOdometryTranslation;
}
bool IsOwnCovariance(int component) {
  return component >= Index(NoiseComponent::kOdometryRotationCovariance);
}

// The noise model with only the given components' standard deviations.
NoiseModel OnlyComponents(const NoiseModel& noise,
                          std::initializer_list<int> components) {
  NoiseModel only;
  only.odom_yaw_sigma_deg = 0.0;
  only.odom_yaw_sigma_rel = 0.0;
  only.odom_tilt_sigma_deg = 0.0;
  only.odom_translation_sigma_m = 0.0;
  only.odom_translation_sigma_rel = 0.0;
  only.cam_rotation_sigma_deg = 0.0;
  only.cam_translation_sigma_rel = 0.0;
  only.cam_translation_along_sigma_rel = 0.0;
  for (const int c : components) {
    switch (static_cast<NoiseComponent>(c)) {
      case NoiseComponent::kOdometryYawConstant:
        only.odom_yaw_sigma_deg = noise.odom_yaw_sigma_deg;
        break;
      case NoiseComponent::kOdometryYawProportional:
        only.odom_yaw_sigma_rel = noise.odom_yaw_sigma_rel;
        break;
      case NoiseComponent::kOdometryTilt:
        only.odom_tilt_sigma_deg = noise.odom_tilt_sigma_deg;
        break;
      case NoiseComponent::kOdometryTranslationConstant:
        only.odom_translation_sigma_m = noise.odom_translation_sigma_m;
        break;
      case NoiseComponent::kOdometryTranslationProportional:
        only.odom_translation_sigma_rel = noise.odom_translation_sigma_rel;
        break;
      case NoiseComponent::kCameraRotation:
        only.cam_rotation_sigma_deg = noise.cam_rotation_sigma_deg;
        break;
      case NoiseComponent::kCameraTranslationAcross:
        only.cam_translation_sigma_rel = noise.cam_translation_sigma_rel;
        break;
      case NoiseComponent::kCameraTranslationAlong:
        only.cam_translation_along_sigma_rel =
            noise.CamTranslationAlongSigmaRel();
        break;
      default:
        break;
    }
  }
  return only;
}

// Contribution to Cov(r) of the given components (all on one side: odometry
// or camera) at the starting noise; zero where the pair's own covariance
// replaces the model or the other way round.
Matrix6d Contribution(const MotionPair& pair,
                      const Rigid3d& odom_from_cam,
                      double scale,
                      const NoiseModel& start_noise,
                      std::initializer_list<int> components) {
  const int first = *components.begin();
  const bool odometry = IsOdometry(first);
  const bool own = IsOwnCovariance(first);
  const std::optional<MotionCovariance>& given =
      odometry ? pair.odom_covariance : pair.cam_covariance;
  if (own != given.has_value()) return Matrix6d::Zero();
  MotionPair masked = pair;
  masked.odom_interpolation_covariance.reset();
  (odometry ? masked.cam_covariance : masked.odom_covariance) =
      MotionCovariance::Zero();
  NoiseModel noise = start_noise;
  if (own) {
    std::vector<int> blocks;
    MotionCovariance covariance = MotionCovariance::Zero();
    for (const int c : components) {
      const int block = GroupOf(static_cast<NoiseComponent>(c)) ==
                                    NoiseGroup::kOdometryRotation ||
                                GroupOf(static_cast<NoiseComponent>(c)) ==
                                    NoiseGroup::kCameraRotation
                            ? 0
                            : 1;
      blocks.push_back(block);
    }
    const MotionCovariance& full = *given;
    if (blocks.size() == 2) {
      covariance = full;
    } else {
      covariance.block<3, 3>(3 * blocks[0], 3 * blocks[0]) =
          full.block<3, 3>(3 * blocks[0], 3 * blocks[0]);
    }
    (odometry ? masked.odom_covariance : masked.cam_covariance) = covariance;
  } else {
    noise = OnlyComponents(start_noise, components);
  }
  return HandEyeResidualCovariance(masked, odom_from_cam, scale, noise);
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
  // W_c: each component alone at the starting noise.
  std::array<Matrix6d, kNumNoiseComponents> contributions;
  // X of kCoupled[k]: Cov(both) - W_a - W_b.
  std::array<Matrix6d, kNumCoupled> coupled;
  Matrix6d interpolation;  // unscaled
};

// One pair's covariance as a quadratic form in the parameters' sqrt(mu):
// bases[p] (the terms in mu_p), and cross terms sqrt(mu_p mu_q) X.
struct Cross {
  int p, q;
  Matrix6d x;
};
struct PairForm {
  std::vector<Matrix6d> bases;  // one per parameter, the fixed one last
  std::vector<Cross> crosses;
};

// parameter_of[c]: the parameter of component c (num_free: the fixed one).
std::vector<PairForm> Forms(
    const std::vector<PairTerms>& terms,
    const std::array<int, kNumNoiseComponents>& parameter_of,
    int num_free) {
  std::vector<PairForm> forms(terms.size());
  for (size_t i = 0; i < terms.size(); ++i) {
    PairForm& form = forms[i];
    form.bases.assign(num_free + 1, Matrix6d::Zero());
    for (int c = 0; c < kNumNoiseComponents; ++c) {
      form.bases[parameter_of[c]] += terms[i].contributions[c];
    }
    for (int k = 0; k < kNumCoupled; ++k) {
      const Matrix6d& x = terms[i].coupled[k];
      if (x.isZero(0.0)) continue;
      const int p = parameter_of[Index(kCoupled[k].first)];
      const int q = parameter_of[Index(kCoupled[k].second)];
      if (p == q) {
        form.bases[p] += x;
      } else {
        form.crosses.push_back({p, q, x});
      }
    }
  }
  return forms;
}

// Sums of one pass over the pairs at the given parameter multipliers.
struct Pass {
  Eigen::VectorXd weighted_sum;     // q_p = sum e^T P D_p P e
  Eigen::VectorXd redundancy_part;  // t_p = sum tr(D_p M)
  Eigen::MatrixXd helmert;          // H_pq = sum tr(M D_p M D_q)
};

// The free parameters' multipliers followed by the fixed parameter's, 1.
Eigen::VectorXd WithFixedParameter(const Eigen::VectorXd& mu) {
  Eigen::VectorXd all(mu.size() + 1);
  all << mu, 1.0;
  return all;
}

// One pair's Cov(r) at the multipliers `all` (the free parameters', then
// the fixed one's 1) and its derivatives D_p by the free multipliers.
Matrix6d PairCovariance(const PairTerms& term,
                        const PairForm& form,
                        const Eigen::VectorXd& all,
                        Matrix6d* derivatives) {
  const int num_free = static_cast<int>(all.size()) - 1;
  Matrix6d covariance = term.interpolation;
  for (int p = 0; p <= num_free; ++p) covariance += all(p) * form.bases[p];
  for (int p = 0; p < num_free; ++p) derivatives[p] = form.bases[p];
  for (const Cross& cross : form.crosses) {
    covariance += std::sqrt(all(cross.p) * all(cross.q)) * cross.x;
    if (cross.p < num_free) {
      derivatives[cross.p] +=
          0.5 * std::sqrt(all(cross.q) / all(cross.p)) * cross.x;
    }
    if (cross.q < num_free) {
      derivatives[cross.q] +=
          0.5 * std::sqrt(all(cross.p) / all(cross.q)) * cross.x;
    }
  }
  covariance.diagonal().array() += 1e-12 * covariance.trace() + 1e-300;
  return covariance;
}

// mu: one multiplier per free parameter.
Pass Evaluate(const std::vector<PairTerms>& terms,
              const std::vector<PairForm>& forms,
              const Eigen::VectorXd& mu) {
  const int num_free = static_cast<int>(mu.size());
  const Eigen::VectorXd all = WithFixedParameter(mu);
  const int num_columns = static_cast<int>(terms.front().jacobian.cols());
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(num_columns, num_columns);
  std::vector<Matrix6d> precisions(terms.size());
  // derivatives[i * num_free + p]: D_p of pair i.
  std::vector<Matrix6d> derivatives(terms.size() * num_free);
  for (size_t i = 0; i < terms.size(); ++i) {
    const Matrix6d covariance = PairCovariance(
        terms[i], forms[i], all, derivatives.data() + i * num_free);
    precisions[i] = covariance.ldlt().solve(Matrix6d::Identity());
    normal += terms[i].jacobian.transpose() * precisions[i] * terms[i].jacobian;
  }
  const Eigen::MatrixXd normal_inverse =
      normal.completeOrthogonalDecomposition().pseudoInverse();
  // tr(A B) without forming A B: the sum of A .* B^T (36 products, not 216).
  const auto trace_of_product = [](const Matrix6d& a, const Matrix6d& b) {
    return a.cwiseProduct(b.transpose()).sum();
  };
  Pass pass;
  pass.weighted_sum = Eigen::VectorXd::Zero(num_free);
  pass.redundancy_part = Eigen::VectorXd::Zero(num_free);
  pass.helmert = Eigen::MatrixXd::Zero(num_free, num_free);
  std::vector<Matrix6d> md(num_free);
  for (size_t i = 0; i < terms.size(); ++i) {
    const Matrix6d& p = precisions[i];
    const Matrix6X pj = p * terms[i].jacobian;
    const Matrix6d m = p - pj * normal_inverse * pj.transpose();
    const Vector6d pe = p * terms[i].residual;
    for (int c = 0; c < num_free; ++c) {
      const Matrix6d& d = derivatives[i * num_free + c];
      pass.weighted_sum(c) += pe.dot(d * pe);
      pass.redundancy_part(c) += trace_of_product(d, m);
      md[c] = m * d;
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

// The Kenward-Roger term A of the estimate's covariance with estimated noise
// (Kenward & Roger 1997, eq. 3 and 4 without the second derivatives, which
// only the cross terms of added standard deviations have): Phi + 2 Phi A Phi
// with Phi = N^-1, A = sum_pq W_pq (Q_pq - P_p Phi P_q), P_p = sum J^T P D_p
// P J, Q_pq = sum J^T P D_p P D_q P J and W the multipliers' covariance.
// Phi alone treats the estimated noise as known; with a few pairs the
// weights' own errors add to the estimate's.
Eigen::MatrixXd KenwardRogerTerm(const std::vector<PairTerms>& terms,
                                 const std::vector<PairForm>& forms,
                                 const Eigen::VectorXd& mu,
                                 const Eigen::MatrixXd& multiplier_covariance) {
  const int num_free = static_cast<int>(mu.size());
  const Eigen::VectorXd all = WithFixedParameter(mu);
  const int num_columns = static_cast<int>(terms.front().jacobian.cols());
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(num_columns, num_columns);
  std::vector<Eigen::MatrixXd> first(num_free, normal);
  std::vector<Eigen::MatrixXd> second(num_free * num_free, normal);
  std::vector<Matrix6d> derivatives(num_free);
  std::vector<Matrix6X> pdpj(num_free);
  for (size_t i = 0; i < terms.size(); ++i) {
    const Matrix6d covariance =
        PairCovariance(terms[i], forms[i], all, derivatives.data());
    const Matrix6d precision = covariance.ldlt().solve(Matrix6d::Identity());
    const Matrix6X pj = precision * terms[i].jacobian;
    normal += terms[i].jacobian.transpose() * pj;
    for (int p = 0; p < num_free; ++p) {
      pdpj[p] = derivatives[p] * pj;
      first[p] += pj.transpose() * pdpj[p];
    }
    for (int p = 0; p < num_free; ++p) {
      for (int q = 0; q < num_free; ++q) {
        second[p * num_free + q] += pdpj[p].transpose() * precision * pdpj[q];
      }
    }
  }
  const Eigen::MatrixXd phi =
      normal.completeOrthogonalDecomposition().pseudoInverse();
  Eigen::MatrixXd term = Eigen::MatrixXd::Zero(num_columns, num_columns);
  for (int p = 0; p < num_free; ++p) {
    for (int q = 0; q < num_free; ++q) {
      const double w = multiplier_covariance(p, q);
      if (w == 0.0) continue;
      term += w * (second[p * num_free + q] - first[p] * phi * first[q]);
    }
  }
  return 0.5 * (term + term.transpose());
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

std::string ToString(NoiseComponent component) {
  switch (component) {
    case NoiseComponent::kOdometryYawConstant:
      return "odometry yaw (constant)";
    case NoiseComponent::kOdometryYawProportional:
      return "odometry yaw (proportional)";
    case NoiseComponent::kOdometryTilt:
      return "odometry tilt";
    case NoiseComponent::kOdometryTranslationConstant:
      return "odometry translation (constant)";
    case NoiseComponent::kOdometryTranslationProportional:
      return "odometry translation (proportional)";
    case NoiseComponent::kCameraRotation:
      return "camera rotation";
    case NoiseComponent::kCameraTranslationAcross:
      return "camera translation (across the motion)";
    case NoiseComponent::kCameraTranslationAlong:
      return "camera translation (along the motion)";
    case NoiseComponent::kOdometryRotationCovariance:
      return "odometry rotation (own covariances)";
    case NoiseComponent::kOdometryTranslationCovariance:
      return "odometry translation (own covariances)";
    case NoiseComponent::kCameraRotationCovariance:
      return "camera rotation (own covariances)";
    case NoiseComponent::kCameraTranslationCovariance:
      return "camera translation (own covariances)";
  }
  return "unknown";
}

NoiseGroup GroupOf(NoiseComponent component) {
  switch (component) {
    case NoiseComponent::kOdometryYawConstant:
    case NoiseComponent::kOdometryYawProportional:
    case NoiseComponent::kOdometryTilt:
    case NoiseComponent::kOdometryRotationCovariance:
      return NoiseGroup::kOdometryRotation;
    case NoiseComponent::kOdometryTranslationConstant:
    case NoiseComponent::kOdometryTranslationProportional:
    case NoiseComponent::kOdometryTranslationCovariance:
      return NoiseGroup::kOdometryTranslation;
    case NoiseComponent::kCameraRotation:
    case NoiseComponent::kCameraRotationCovariance:
      return NoiseGroup::kCameraRotation;
    default:
      return NoiseGroup::kCameraTranslation;
  }
}

double NoiseEstimate::SigmaRatio(NoiseGroup group) const {
  return std::sqrt(variance_factors[Index(group)]);
}

double NoiseEstimate::SigmaRatio(NoiseComponent component) const {
  return std::sqrt(component_factors[Index(component)]);
}

NoiseModel ScaleNoise(const NoiseModel& noise, const NoiseFactors& factors) {
  const double odom_rotation =
      std::sqrt(factors[Index(NoiseGroup::kOdometryRotation)]);
  const double odom_translation =
      std::sqrt(factors[Index(NoiseGroup::kOdometryTranslation)]);
  const double cam_translation =
      std::sqrt(factors[Index(NoiseGroup::kCameraTranslation)]);
  NoiseModel scaled = noise;
  scaled.odom_yaw_sigma_deg *= odom_rotation;
  scaled.odom_yaw_sigma_rel *= odom_rotation;
  scaled.odom_tilt_sigma_deg *= odom_rotation;
  scaled.odom_translation_sigma_m *= odom_translation;
  scaled.odom_translation_sigma_rel *= odom_translation;
  scaled.cam_rotation_sigma_deg *=
      std::sqrt(factors[Index(NoiseGroup::kCameraRotation)]);
  scaled.cam_translation_sigma_rel *= cam_translation;
  if (scaled.cam_translation_along_sigma_rel > 0.0) {
    scaled.cam_translation_along_sigma_rel *= cam_translation;
  }
  return scaled;
}

NoiseModel ScaleNoiseComponents(const NoiseModel& noise,
                                const ComponentFactors& factors) {
  const auto ratio = [&](NoiseComponent component) {
    return std::sqrt(factors[Index(component)]);
  };
  NoiseModel scaled = noise;
  scaled.odom_yaw_sigma_deg *= ratio(NoiseComponent::kOdometryYawConstant);
  scaled.odom_yaw_sigma_rel *= ratio(NoiseComponent::kOdometryYawProportional);
  scaled.odom_tilt_sigma_deg *= ratio(NoiseComponent::kOdometryTilt);
  scaled.odom_translation_sigma_m *=
      ratio(NoiseComponent::kOdometryTranslationConstant);
  scaled.odom_translation_sigma_rel *=
      ratio(NoiseComponent::kOdometryTranslationProportional);
  scaled.cam_rotation_sigma_deg *= ratio(NoiseComponent::kCameraRotation);
  scaled.cam_translation_sigma_rel *=
      ratio(NoiseComponent::kCameraTranslationAcross);
  scaled.cam_translation_along_sigma_rel =
      noise.CamTranslationAlongSigmaRel() *
      ratio(NoiseComponent::kCameraTranslationAlong);
  return scaled;
}

NoiseFactors CovarianceFactors(const ComponentFactors& factors) {
  return {factors[Index(NoiseComponent::kOdometryRotationCovariance)],
          factors[Index(NoiseComponent::kOdometryTranslationCovariance)],
          factors[Index(NoiseComponent::kCameraRotationCovariance)],
          factors[Index(NoiseComponent::kCameraTranslationCovariance)]};
}

MotionPairs ScaleCovariances(const MotionPairs& pairs,
                             const NoiseEstimate& estimate) {
  return ScaleCovariances(pairs, CovarianceFactors(estimate.component_factors));
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
                            const ComponentFactors& start) {
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

  std::vector<PairTerms> terms;
  std::array<double, kNumNoiseComponents> trace = {};
  std::array<double, kNumCoupled> coupled_trace = {};
  for (const int i : used) {
    const MotionPair pair = ScaleCovariances({pairs[i]}, start_covariance)[0];
    const double scale = metric_scales.at(pair.segment);
    PairTerms term;
    term.residual = HandEyeResidual(pair, odom_from_cam, scale);
    term.jacobian = ResidualJacobian(pair,
                                     odom_from_cam,
                                     scale,
                                     scale_columns.at(pair.segment),
                                     num_columns,
                                     estimate_z);
    for (int c = 0; c < kNumNoiseComponents; ++c) {
      term.contributions[c] =
          Contribution(pair, odom_from_cam, scale, start_noise, {c});
      trace[c] += term.contributions[c].trace();
    }
    for (int k = 0; k < kNumCoupled; ++k) {
      const int a = Index(kCoupled[k].first), b = Index(kCoupled[k].second);
      term.coupled[k].setZero();
      if (term.contributions[a].isZero(0.0) ||
          term.contributions[b].isZero(0.0)) {
        continue;
      }
      term.coupled[k] =
          Contribution(pair, odom_from_cam, scale, start_noise, {a, b}) -
          term.contributions[a] - term.contributions[b];
      coupled_trace[k] += term.coupled[k].trace();
    }
    term.interpolation =
        InterpolationContribution(pair, odom_from_cam, scale, options.noise);
    terms.push_back(std::move(term));
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
  Pass pass;
  std::array<double, kNumNoiseComponents> last_multiplier;
  last_multiplier.fill(1.0);
  while (!parameters.empty()) {
    const int num_free = static_cast<int>(parameters.size());
    std::array<int, kNumNoiseComponents> parameter_of;
    parameter_of.fill(num_free);
    for (int p = 0; p < num_free; ++p) {
      for (const int c : parameters[p]) parameter_of[c] = p;
    }
    const std::vector<PairForm> forms = Forms(terms, parameter_of, num_free);
    // Warm start: a tie starts from its first member's last multiplier.
    mu.resize(num_free);
    for (int p = 0; p < num_free; ++p) {
      mu(p) = last_multiplier[parameters[p].front()];
    }
    int iteration = 0;
    bool converged = false;
    std::vector<bool> held(num_free, false);
    for (; iteration < kMaxIterations; ++iteration) {
      pass = Evaluate(terms, forms, mu);
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
          Uncertainty(pass, mu, parameters, held).worst_relative >
              kMaxRelativeStddev) {
        break;
      }
      if (free.empty()) {
        converged = true;
        break;
      }
      // Fisher scoring (Helmert's step where Cov is linear in mu) converges
      // in a few iterations; where it fails, Foerstner's multiplicative step.
      const Eigen::MatrixXd helmert = pass.helmert(free, free);
      const Eigen::VectorXd step =
          helmert.completeOrthogonalDecomposition().solve(
              Eigen::VectorXd(score(free)));
      double change = 0.0;
      for (size_t k = 0; k < free.size(); ++k) {
        const int p = free[k];
        double next = mu(p) + step(k);
        if (!std::isfinite(next)) {
          next = pass.redundancy_part(p) > 0.0
                     ? mu(p) * pass.weighted_sum(p) / pass.redundancy_part(p)
                     : mu(p);
        }
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
      pass = Evaluate(terms, forms, mu);
      const Eigen::VectorXd score = pass.weighted_sum - pass.redundancy_part;
      for (int p = 0; p < num_free; ++p) {
        held[p] = mu(p) <= kMinMultiplier && score(p) <= 0.0;
      }
    }
    for (int p = 0; p < num_free; ++p) {
      for (const int c : parameters[p]) last_multiplier[c] = mu(p);
    }
    const MultiplierUncertainty uncertainty =
        Uncertainty(pass, mu, parameters, held);
    const Eigen::MatrixXd& covariance = uncertainty.covariance;
    const Eigen::VectorXd& relative = uncertainty.relative;
    const int worst = uncertainty.worst;
    if (uncertainty.worst_relative <= kMaxRelativeStddev) {
      // In the refinement's columns, which hold z (WidenForEstimatedNoise).
      if (!estimate_z) {
        estimate.kenward_roger_term =
            KenwardRogerTerm(terms, forms, mu, covariance);
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
              mu(p) * pass.redundancy_part(p) / parameters[p].size();
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

std::string NoiseSummary(const NoiseEstimate& estimate) {
  std::ostringstream text;
  text << "noise estimated from " << estimate.num_pairs
       << " pairs (standard deviations relative to the given noise): ";
  bool first = true;
  std::vector<std::string> kept;
  for (int c = 0; c < kNumNoiseComponents; ++c) {
    if (!estimate.component_present[c]) continue;
    if (!estimate.component_estimated[c]) {
      if (c != Index(NoiseComponent::kOdometryTilt)) {
        kept.push_back(ToString(static_cast<NoiseComponent>(c)));
      }
      continue;
    }
    if (estimate.component_tie[c] != c) continue;  // with its representative
    std::vector<std::string> members;
    for (int d = 0; d < kNumNoiseComponents; ++d) {
      if (estimate.component_estimated[d] && estimate.component_tie[d] == c) {
        members.push_back(ToString(static_cast<NoiseComponent>(d)));
      }
    }
    text << (first ? "" : ", ") << members[0];
    for (size_t k = 1; k < members.size(); ++k) {
      text << (k + 1 == members.size() ? " and " : ", ") << members[k];
    }
    if (members.size() > 1) text << " (tied: not separable)";
    text << " x" << Ratio(estimate.SigmaRatio(static_cast<NoiseComponent>(c)));
    first = false;
  }
  if (first) text << "none determined";
  if (!kept.empty()) {
    text << "; kept as given: ";
    for (size_t k = 0; k < kept.size(); ++k) {
      text << (k == 0 ? "" : ", ") << kept[k];
    }
    text << " (not determined by these pairs)";
  }
  if (estimate.stddev_widening >= 1.005) {
    std::ostringstream percent;
    percent.setf(std::ios::fixed);
    percent.precision(1);
    percent << 100.0 * (estimate.stddev_widening - 1.0);
    text << "; standard deviations widened by up to " << percent.str()
         << " % for this estimate's own uncertainty (Kenward-Roger)";
  }
  return text.str();
}

}  // namespace odomcal
