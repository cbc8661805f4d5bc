// The F tail is a regularised incomplete beta function,
//   P(F > f) = I_x(d2 / 2, d1 / 2),  x = d2 / (d2 + d1 f),
// evaluated by its continued fraction (modified Lentz), as in Numerical
// Recipes, section 6.4; the critical value by bisection on log f.

#include "odomcal/solver/f_distribution.h"

#include <cmath>

namespace odomcal {
namespace {

double BetaContinuedFraction(double a, double b, double x) {
  constexpr double kTiny = 1e-300;
  constexpr double kEpsilon = 1e-15;
  double c = 1.0;
  double d = 1.0 - (a + b) * x / (a + 1.0);
  if (std::abs(d) < kTiny) d = kTiny;
  d = 1.0 / d;
  double h = d;
  for (int m = 1; m <= 1000; ++m) {
    const double m2 = 2.0 * m;
    double aa = m * (b - m) * x / ((a + m2 - 1.0) * (a + m2));
    d = 1.0 + aa * d;
    if (std::abs(d) < kTiny) d = kTiny;
    c = 1.0 + aa / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    h *= d * c;
    aa = -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1.0));
    d = 1.0 + aa * d;
    if (std::abs(d) < kTiny) d = kTiny;
    c = 1.0 + aa / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < kEpsilon) break;
  }
  return h;
}

// I_x(a, b).
double RegularizedIncompleteBeta(double a, double b, double x) {
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0;
  const double log_front = std::lgamma(a + b) - std::lgamma(a) -
                           std::lgamma(b) + a * std::log(x) +
                           b * std::log1p(-x);
  if (x < (a + 1.0) / (a + b + 2.0)) {
    return std::exp(log_front) * BetaContinuedFraction(a, b, x) / a;
  }
  return 1.0 - std::exp(log_front) * BetaContinuedFraction(b, a, 1.0 - x) / b;
}

}  // namespace

double FDistributionUpperTail(double f, double d1, double d2) {
  if (!(f > 0.0)) return 1.0;
  return RegularizedIncompleteBeta(0.5 * d2, 0.5 * d1, d2 / (d2 + d1 * f));
}

double FDistributionCriticalValue(double probability, double d1, double d2) {
  double low = 1e-12, high = 1.0;
  while (FDistributionUpperTail(high, d1, d2) > probability && high < 1e300)
    high *= 2.0;
  for (int iteration = 0; iteration < 200; ++iteration) {
    const double middle = std::sqrt(low * high);
    (FDistributionUpperTail(middle, d1, d2) > probability ? low : high) =
        middle;
    if (high / low < 1.0 + 1e-12) break;
  }
  return high;
}

}  // namespace odomcal
