#include "odomcal/solver/f_distribution.h"

#include <gtest/gtest.h>

#include <cmath>

namespace odomcal {
namespace {

// Reference values from statistical tables (R: pf, qf).
TEST(FDistribution, UpperTailMatchesTables) {
  // F(1, d) = t_d^2: the two-sided t tail.
  EXPECT_NEAR(FDistributionUpperTail(10.04429, 1, 10), 0.01, 1e-6);
  EXPECT_NEAR(FDistributionUpperTail(3.492828, 2, 20), 0.05, 1e-6);
  EXPECT_NEAR(FDistributionUpperTail(1.0, 5, 5), 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(FDistributionUpperTail(0.0, 3, 7), 1.0);
  EXPECT_NEAR(FDistributionUpperTail(3.841459 * 1.0, 1, 1e7), 0.05, 1e-5);
}

TEST(FDistribution, CriticalValueInvertsTheTail) {
  EXPECT_NEAR(FDistributionCriticalValue(0.01, 1, 10), 10.04429, 1e-4);
  EXPECT_NEAR(FDistributionCriticalValue(0.05, 2, 20), 3.492828, 1e-5);
  for (const double probability : {0.1, 1e-3, 1e-6, 1e-9}) {
    const double f = FDistributionCriticalValue(probability, 1, 48);
    EXPECT_NEAR(FDistributionUpperTail(f, 1, 48) / probability, 1.0, 1e-6);
  }
}

}  // namespace
}  // namespace odomcal
