// Noise models and pair covariances scaled by variance factors, per
// component or per group (noise_components.h).
#pragma once

#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/motion_pair.h"
#include "odomcal/solver/noise_components.h"

namespace odomcal {

// The noise model with each component's standard deviation scaled by
// sqrt(factor) (the along-track camera noise made explicit).
NoiseModel ScaleNoiseComponents(const NoiseModel& noise,
                                const ComponentFactors& factors);
// The factors of the pairs' own covariances, per group (ScaleCovariances).
NoiseFactors CovarianceFactors(const ComponentFactors& factors);

// The noise model with each group's standard deviations scaled by
// sqrt(factor) (the noise's shape kept).
NoiseModel ScaleNoise(const NoiseModel& noise, const NoiseFactors& factors);

// The pairs with their own covariances (where present) scaled by group: the
// rotation and translation blocks by their factors, the cross blocks by the
// geometric mean.
MotionPairs ScaleCovariances(const MotionPairs& pairs,
                             const NoiseFactors& factors);
// The same for one pair.
MotionPair ScaleCovariancesOfPair(const MotionPair& pair,
                                  const NoiseFactors& factors);

}  // namespace odomcal
