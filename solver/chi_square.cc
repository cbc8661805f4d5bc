// P(X > x) = Q(dof / 2, x / 2), the regularised upper incomplete gamma
// function: its power series below a + 1, its continued fraction (modified
// Lentz) above, as in Numerical Recipes, section 6.2; the critical value by
// bisection on log x.

#include "odomcal/solver/chi_square.h"

#include <cmath>

namespace odomcal {
namespace {

constexpr double kEpsilon = 1e-15;
constexpr double kTiny = 1e-300;

// P(a, x) by its series, for x < a + 1.
double LowerGammaSeries(double a, double x) {
  double term = 1.0 / a;
  double sum = term;
  for (int n = 1; n <= 10000; ++n) {
    term *= x / (a + n);
    sum += term;
    if (std::abs(term) < std::abs(sum) * kEpsilon) break;
  }
  return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

// Q(a, x) by its continued fraction, for x >= a + 1.
double UpperGammaContinuedFraction(double a, double x) {
  double b = x + 1.0 - a;
  double c = 1.0 / kTiny;
  double d = 1.0 / b;
  double h = d;
  for (int i = 1; i <= 10000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < kEpsilon) break;
  }
  return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

}  // namespace

double ChiSquareUpperTail(double x, double dof) {
  if (!(x > 0.0)) return 1.0;
  const double a = 0.5 * dof;
  const double half = 0.5 * x;
  if (half < a + 1.0) return 1.0 - LowerGammaSeries(a, half);
  return UpperGammaContinuedFraction(a, half);
}

double ChiSquareCriticalValue(double probability, double dof) {
  if (!(dof > 0.0)) return 0.0;
  double low = 1e-12, high = dof + 1.0;
  while (ChiSquareUpperTail(high, dof) > probability && high < 1e300) {
    high *= 2.0;
  }
  for (int iteration = 0; iteration < 200; ++iteration) {
    const double middle = std::sqrt(low * high);
    (ChiSquareUpperTail(middle, dof) > probability ? low : high) = middle;
    if (high / low < 1.0 + 1e-13) break;
  }
  return high;
}

double ChiSquare999(double dof) { return ChiSquareCriticalValue(1e-3, dof); }

}  // namespace odomcal
