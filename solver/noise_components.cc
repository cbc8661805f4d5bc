// Names and groups of the noise components (noise_components.h).

#include "odomcal/solver/noise_components.h"

#include <string>

namespace odomcal {

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

}  // namespace odomcal
