#include "odomcal/solver/chi_square.h"

#include <gtest/gtest.h>

#include <cmath>

namespace odomcal {
namespace {

// Table values (R: qchisq(0.999, dof), pchisq(x, dof, lower = FALSE)).
TEST(ChiSquare, CriticalValuesMatchTables) {
  EXPECT_NEAR(ChiSquare999(1), 10.827566, 1e-5);
  EXPECT_NEAR(ChiSquare999(3), 16.266236, 1e-5);
  EXPECT_NEAR(ChiSquare999(6), 22.457744, 1e-5);
  EXPECT_NEAR(ChiSquare999(10), 29.588298, 1e-5);
  EXPECT_NEAR(ChiSquare999(100), 149.449252, 1e-4);
  EXPECT_NEAR(ChiSquare999(1000), 1143.916596, 1e-3);
  EXPECT_NEAR(ChiSquareCriticalValue(0.05, 2), -2.0 * std::log(0.05), 1e-9);
  EXPECT_EQ(ChiSquare999(0), 0.0);
}

TEST(ChiSquare, UpperTailMatchesClosedForms) {
  // dof 2: exp(-x/2); dof 1: erfc(sqrt(x/2)).
  for (const double x : {0.1, 1.0, 5.0, 30.0}) {
    EXPECT_NEAR(ChiSquareUpperTail(x, 2), std::exp(-0.5 * x), 1e-13);
    EXPECT_NEAR(ChiSquareUpperTail(x, 1), std::erfc(std::sqrt(0.5 * x)), 1e-13);
  }
  EXPECT_EQ(ChiSquareUpperTail(0.0, 4), 1.0);
  EXPECT_NEAR(ChiSquareUpperTail(ChiSquare999(7), 7), 1e-3, 1e-12);
}

}  // namespace
}  // namespace odomcal
