// Whether the two-view estimates of a landmark simulation match their
// covariances: the normalised estimation error squared (NEES) of each camera
// motion over its 5 observable dimensions (rotation 3, translation
// direction 2; two views carry no length), and the rate of gross errors.
//
// A consistent estimator has NEES ~ chi-square(5): median 4.35, 99th
// percentile 15.09. A heavy tail means motions whose covariance calls them
// accurate when they are not, which the weighted batch methods trust.
#pragma once

#include "odomcal/datasets/paper/paper_simulation.h"

#include <vector>

namespace odomcal {

// Gross: the translation direction more than this far off the truth (the
// error that dominated the landmark reproduction before multi-start).
constexpr double kGrossDirectionErrorDeg = 15.0;
// Chi-square(5) quantiles, for comparison.
constexpr double kChiSquare5Median = 4.351;
constexpr double kChiSquare5Quantile99 = 15.086;

// Errors of the camera motions of simulations, one entry per motion.
struct TwoViewErrors {
  std::vector<double> nees;
  std::vector<double> direction_error_deg;
};

// Appends the errors of `simulation`'s inlier camera motions (those with a
// covariance: landmark mode).
void AddTwoViewErrors(const PaperSimulation& simulation, TwoViewErrors* errors);

struct TwoViewConsistency {
  int num_motions = 0;
  double nees_median = 0.0;
  double nees_quantile_90 = 0.0;
  double nees_quantile_99 = 0.0;
  double nees_max = 0.0;
  double gross_error_rate = 0.0;  // fraction beyond kGrossDirectionErrorDeg
};

TwoViewConsistency SummarizeTwoViewErrors(const TwoViewErrors& errors);

}  // namespace odomcal
