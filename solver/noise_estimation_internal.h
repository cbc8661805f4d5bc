// Shared by the noise estimation's sources (noise_estimation.cc,
// noise_pair_terms.cc, noise_kenward_roger.cc, noise_summary.cc,
// noise_scaling.cc); internal: not installed. The components are
// worked on as "parameters": a parameter is a set of tied components with
// one multiplier on their standard deviations' squares (relative to the
// starting factors); components that are kept at the given noise form the
// fixed parameter, whose multiplier stays 1.
#pragma once

#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/hand_eye_residual.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/noise_components.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>

#include <array>
#include <initializer_list>
#include <utility>
#include <vector>

namespace odomcal::internal {

using Matrix6X = Eigen::Matrix<double, 6, Eigen::Dynamic>;

inline int Index(NoiseGroup group) { return static_cast<int>(group); }
inline int Index(NoiseComponent component) {
  return static_cast<int>(component);
}

// Components whose standard deviations add (a constant and a proportional
// part; the rotation and translation blocks of an own covariance, whose
// cross block scales with both): Cov has a term sqrt(mu_a mu_b) X_ab.
inline constexpr std::pair<NoiseComponent, NoiseComponent> kCoupled[] = {
    {NoiseComponent::kOdometryYawConstant,
     NoiseComponent::kOdometryYawProportional},
    {NoiseComponent::kOdometryTranslationConstant,
     NoiseComponent::kOdometryTranslationProportional},
    {NoiseComponent::kOdometryRotationCovariance,
     NoiseComponent::kOdometryTranslationCovariance},
    {NoiseComponent::kCameraRotationCovariance,
     NoiseComponent::kCameraTranslationCovariance},
};
inline constexpr int kNumCoupled = 4;

// Contribution to Cov(r) of the given components (all on one side: odometry
// or camera) at the starting noise; zero where the pair's own covariance
// replaces the model or the other way round. `step`: the pair's
// ModelledStep under the full starting noise, which sizes every part as it
// sizes their sum; `jacobians`: the pair's HandEyeResidualNoiseJacobians.
Matrix6d Contribution(const MotionPair& pair,
                      const ResidualNoiseJacobians& jacobians,
                      const NoiseModel& start_noise,
                      const StepSize& step,
                      std::initializer_list<int> components);

// Contribution of the odometry's interpolation error to Cov(r), which no
// noise factor scales (zero for pairs without one).
Matrix6d InterpolationContribution(const MotionPair& pair,
                                   const Rigid3d& odom_from_cam,
                                   double scale,
                                   const NoiseModel& noise);

// d r / d [phi(3), p_x, p_y, (p_z), s_k...]: the rotation columns by
// central differences, the others exactly (r is linear in p and s).
Matrix6X ResidualJacobian(const MotionPair& pair,
                          const Rigid3d& odom_from_cam,
                          double scale,
                          int scale_column,
                          int num_columns,
                          bool estimate_z);

// One term of a pair's Cov(r): sqrt(mu_a mu_b) x, with mu_c the multiplier
// of component c's parameter. a == b: the component's contribution W_a at
// the starting noise (mu_a x); a != b: the cross term X of kCoupled,
// Cov(both) - W_a - W_b.
struct CovariancePart {
  int a = 0;
  int b = 0;
  Matrix6d x;
};

// Only the nonzero parts are kept: a pair has either the model's components
// or its own covariances, so about half are zero, and at 10 000 pairs each
// Matrix6d kept is 2.9 MB.
struct PairTerms {
  Vector6d residual;
  Matrix6X jacobian;
  std::vector<CovariancePart> parts;
  Matrix6d interpolation;  // unscaled
};

// parameter_of[c]: the parameter of component c, num_free (the number of
// free parameters) for the fixed one, whose multiplier is 1.
using ParameterOf = std::array<int, kNumNoiseComponents>;

// The free parameters' multipliers followed by the fixed parameter's, 1.
Eigen::VectorXd WithFixedParameter(const Eigen::VectorXd& mu);

// One pair's Cov(r) at the multipliers `all` (the free parameters', then
// the fixed one's 1) and, where `derivatives` is given, its derivatives D_p
// by the free multipliers.
Matrix6d PairCovariance(const PairTerms& term,
                        const ParameterOf& parameter_of,
                        const Eigen::VectorXd& all,
                        Matrix6d* derivatives);
// The derivatives D_p alone.
void PairCovarianceDerivatives(const PairTerms& term,
                               const ParameterOf& parameter_of,
                               const Eigen::VectorXd& all,
                               Matrix6d* derivatives);

// The Kenward-Roger term A of the estimate's covariance with estimated noise
// (Kenward & Roger 1997, eq. 3 and 4 without the second derivatives, which
// only the cross terms of added standard deviations have): Phi + 2 Phi A Phi
// with Phi = N^-1, A = sum_pq W_pq (Q_pq - P_p Phi P_q), P_p = sum J^T P D_p
// P J, Q_pq = sum J^T P D_p P D_q P J and W the multipliers' covariance.
// Phi alone treats the estimated noise as known; with a few pairs the
// weights' own errors add to the estimate's.
Eigen::MatrixXd KenwardRogerTerm(const std::vector<PairTerms>& terms,
                                 const ParameterOf& parameter_of,
                                 const Eigen::VectorXd& mu,
                                 const Eigen::MatrixXd& multiplier_covariance,
                                 int num_threads);

}  // namespace odomcal::internal
