// One pair's residual covariance split into the noise components'
// contributions, and evaluated at the parameters' multipliers
// (noise_estimation_internal.h).

#include "odomcal/solver/hand_eye_residual.h"
#include "odomcal/solver/noise_estimation_internal.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <optional>

namespace odomcal::internal {
namespace {

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

}  // namespace

Matrix6d Contribution(const MotionPair& pair,
                      const ResidualNoiseJacobians& jacobians,
                      const NoiseModel& start_noise,
                      const StepSize& step,
                      std::initializer_list<int> components) {
  const int first = *components.begin();
  const bool odometry = IsOdometry(first);
  const bool own = IsOwnCovariance(first);
  const std::optional<MotionCovariance>& given =
      odometry ? pair.odom_covariance : pair.cam_covariance;
  if (own != given.has_value()) return Matrix6d::Zero();
  MotionCovariance covariance = MotionCovariance::Zero();
  if (own) {
    std::vector<int> blocks;
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
      const Eigen::Index first = 3 * static_cast<Eigen::Index>(blocks[0]);
      covariance.block<3, 3>(first, first) = full.block<3, 3>(first, first);
    }
  } else {
    // Without the interpolation error, which no factor scales.
    const NoiseModel noise = OnlyComponents(start_noise, components);
    covariance = odometry ? OdometryNoiseCovariance(pair, noise, step)
                          : CameraCovariance(pair, noise, step);
  }
  const Matrix6d& f = odometry ? jacobians.odometry : jacobians.camera;
  return f * covariance * f.transpose();
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
  // r_t = R_A p + t_A - s R t_B - p is linear in p and s, and r_rot depends
  // on neither.
  const int num_translations = estimate_z ? 3 : 2;
  const Eigen::Matrix3d r_a_minus_identity =
      pair.odom_i_from_odom_j.rotation.toRotationMatrix() -
      Eigen::Matrix3d::Identity();
  for (int k = 0; k < num_translations; ++k) {
    jacobian.col(3 + k).tail<3>() = r_a_minus_identity.col(k);
  }
  jacobian.col(scale_column).tail<3>() =
      -(odom_from_cam.rotation * pair.cam_i_from_cam_j.translation);
  return jacobian;
}

Eigen::VectorXd WithFixedParameter(const Eigen::VectorXd& mu) {
  Eigen::VectorXd all(mu.size() + 1);
  all << mu, 1.0;
  return all;
}

Matrix6d PairCovariance(const PairTerms& term,
                        const ParameterOf& parameter_of,
                        const Eigen::VectorXd& all,
                        Matrix6d* derivatives) {
  Matrix6d covariance = term.interpolation;
  for (const CovariancePart& part : term.parts) {
    const int p = parameter_of[part.a];
    const int q = parameter_of[part.b];
    covariance += (p == q ? all(p) : std::sqrt(all(p) * all(q))) * part.x;
  }
  covariance.diagonal().array() += 1e-12 * covariance.trace() + 1e-300;
  if (derivatives != nullptr) {
    PairCovarianceDerivatives(term, parameter_of, all, derivatives);
  }
  return covariance;
}

void PairCovarianceDerivatives(const PairTerms& term,
                               const ParameterOf& parameter_of,
                               const Eigen::VectorXd& all,
                               Matrix6d* derivatives) {
  const int num_free = static_cast<int>(all.size()) - 1;
  for (int p = 0; p < num_free; ++p) derivatives[p].setZero();
  for (const CovariancePart& part : term.parts) {
    const int p = parameter_of[part.a];
    const int q = parameter_of[part.b];
    if (p == q) {
      if (p < num_free) derivatives[p] += part.x;
      continue;
    }
    // d sqrt(mu_p mu_q) / d mu_p = sqrt(mu_q / mu_p) / 2.
    if (p < num_free) {
      derivatives[p] += 0.5 * std::sqrt(all(q) / all(p)) * part.x;
    }
    if (q < num_free) {
      derivatives[q] += 0.5 * std::sqrt(all(p) / all(q)) * part.x;
    }
  }
}

}  // namespace odomcal::internal
