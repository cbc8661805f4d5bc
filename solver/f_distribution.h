// Upper tail and critical values of Fisher's F distribution, for tests whose
// threshold must follow from a false-alarm probability and the number of
// observations rather than be a fixed number (scale_consistency.h).
#pragma once

namespace odomcal {

// P(F > f) for F ~ F(d1, d2); 1 for f <= 0. d1, d2 > 0.
double FDistributionUpperTail(double f, double d1, double d2);

// The f with P(F > f) = probability, 0 < probability < 1.
double FDistributionCriticalValue(double probability, double d1, double d2);

}  // namespace odomcal
