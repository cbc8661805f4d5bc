// The noise components of the hand-eye residual's covariance and their
// groups (see noise_estimation.h for how their variance factors are
// estimated).
#pragma once

#include <array>
#include <string>

namespace odomcal {

enum class NoiseGroup {
  kOdometryRotation = 0,     // odom_yaw_sigma_*, odom_tilt_sigma_deg
  kOdometryTranslation = 1,  // odom_translation_sigma_*
  kCameraRotation = 2,       // cam_rotation_sigma_deg
  kCameraTranslation = 3,    // cam_translation_sigma_rel
};
constexpr int kNumNoiseGroups = 4;

// "odometry rotation", ... (used in messages and the JSON).
std::string ToString(NoiseGroup group);

// Variance factor per group, indexed by NoiseGroup.
using NoiseFactors = std::array<double, kNumNoiseGroups>;
constexpr NoiseFactors kUnitNoiseFactors = {1.0, 1.0, 1.0, 1.0};

// The estimated components, each with its own variance factor.
enum class NoiseComponent {
  kOdometryYawConstant = 0,              // odom_yaw_sigma_deg
  kOdometryYawProportional = 1,          // odom_yaw_sigma_rel
  kOdometryTilt = 2,                     // odom_tilt_sigma_deg
  kOdometryTranslationConstant = 3,      // odom_translation_sigma_m
  kOdometryTranslationProportional = 4,  // odom_translation_sigma_rel
  kCameraRotation = 5,                   // cam_rotation_sigma_deg
  kCameraTranslationAcross = 6,          // cam_translation_sigma_rel
  kCameraTranslationAlong = 7,           // cam_translation_along_sigma_rel
  kOdometryRotationCovariance = 8,       // the pairs' own covariances
  kOdometryTranslationCovariance = 9,
  kCameraRotationCovariance = 10,
  kCameraTranslationCovariance = 11,
};
constexpr int kNumNoiseComponents = 12;

// "odometry yaw, constant part", ... (used in the summary and the JSON).
std::string ToString(NoiseComponent component);
NoiseGroup GroupOf(NoiseComponent component);

// Variance factor per component, indexed by NoiseComponent.
using ComponentFactors = std::array<double, kNumNoiseComponents>;
constexpr ComponentFactors kUnitComponentFactors = {
    1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0};

}  // namespace odomcal
