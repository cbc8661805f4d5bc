// Noise models and pair covariances scaled by variance factors
// (noise_scaling.h).

#include "odomcal/solver/noise_scaling.h"

#include "odomcal/solver/hand_eye_residual.h"
#include "odomcal/solver/noise_estimation_internal.h"

#include <Eigen/Core>

#include <cmath>

namespace odomcal {
namespace {

using internal::Index;

}  // namespace

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

MotionPair ScaleCovariancesOfPair(const MotionPair& pair,
                                  const NoiseFactors& factors) {
  auto scale =
      [](MotionCovariance* covariance, double rotation, double translation) {
        Vector6d sigma;
        sigma << Eigen::Vector3d::Constant(std::sqrt(rotation)),
            Eigen::Vector3d::Constant(std::sqrt(translation));
        *covariance = sigma.asDiagonal() * *covariance * sigma.asDiagonal();
      };
  MotionPair scaled = pair;
  if (scaled.odom_covariance) {
    scale(&*scaled.odom_covariance,
          factors[Index(NoiseGroup::kOdometryRotation)],
          factors[Index(NoiseGroup::kOdometryTranslation)]);
  }
  if (scaled.cam_covariance) {
    scale(&*scaled.cam_covariance,
          factors[Index(NoiseGroup::kCameraRotation)],
          factors[Index(NoiseGroup::kCameraTranslation)]);
  }
  return scaled;
}

MotionPairs ScaleCovariances(const MotionPairs& pairs,
                             const NoiseFactors& factors) {
  MotionPairs scaled;
  scaled.reserve(pairs.size());
  for (const MotionPair& pair : pairs) {
    scaled.push_back(ScaleCovariancesOfPair(pair, factors));
  }
  return scaled;
}

}  // namespace odomcal
