#include "odomcal/datasets/paper/two_view_direction_scan.h"

#include "odomcal/datasets/paper/two_view_pose.h"
#include "odomcal/datasets/paper/two_view_test_views.h"
#include "odomcal/tests/test_seed.h"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace odomcal {
namespace {

// A well-determined direction (0.5 m against points 1-5 m deep, 0.1 px) is
// left alone: its cost is quadratic over many grid cells.
TEST(ScanTranslationDirection, LeavesAWellDeterminedDirectionAlone) {
  auto rng = SeededRng(721);
  for (int trial = 0; trial < 20; ++trial) {
    const TwoViewTestViews views = RandomTwoViewTestViews(0.5, 0.1, &rng);
    TwoViewOptions options;
    options.pixel_sigma = 0.1;
    options.num_minimal_samples = 0;
    options.covariance_of_other_minima = false;
    const TwoViewEstimate estimate =
        EstimateTwoViewPose(views.u_i, views.u_j, options);
    ASSERT_TRUE(estimate.success) << estimate.failure;
    const DirectionScan scan =
        ScanTranslationDirection(views.u_i,
                                 views.u_j,
                                 estimate.cam_i_from_cam_j,
                                 estimate.covariance,
                                 400.0,
                                 0.1,
                                 200);
    EXPECT_FALSE(scan.scanned);
    EXPECT_EQ(scan.num_cells_used, 0);
    EXPECT_EQ(scan.covariance, estimate.covariance);
  }
}

// Where it runs, the scan only widens (the added spread is positive
// semi-definite), deterministically; no grid or no noise: no scan.
TEST(ScanTranslationDirection, OnlyWidensAndCanBeTurnedOff) {
  auto rng = SeededRng(722);
  int num_widened = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const TwoViewTestViews views = RandomTwoViewTestViews(0.02, 1.0, &rng);
    TwoViewOptions options;
    options.num_minimal_samples = 0;
    options.direction_scan_points = 0;
    const TwoViewEstimate estimate =
        EstimateTwoViewPose(views.u_i, views.u_j, options);
    if (!estimate.success) continue;
    const auto scan = [&](int num_points, double pixel_sigma) {
      return ScanTranslationDirection(views.u_i,
                                      views.u_j,
                                      estimate.cam_i_from_cam_j,
                                      estimate.covariance,
                                      400.0,
                                      pixel_sigma,
                                      num_points);
    };
    const DirectionScan widened = scan(200, 1.0);
    EXPECT_EQ(widened.covariance, scan(200, 1.0).covariance);
    const MotionCovariance spread = widened.covariance - estimate.covariance;
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<MotionCovariance>(spread)
                  .eigenvalues()
                  .minCoeff(),
              -1e-12 * estimate.covariance.trace());
    if (widened.num_cells_used > 0) {
      ++num_widened;
      EXPECT_GT(spread.trace(), 0.0);
    }
    for (const DirectionScan& off : {scan(0, 1.0), scan(200, 0.0)}) {
      EXPECT_FALSE(off.scanned);
      EXPECT_EQ(off.covariance, estimate.covariance);
    }
  }
  EXPECT_GT(num_widened, 10);
}

TEST(ScanTranslationDirection, NegativeGridSizeIsRefused) {
  TwoViewOptions options;
  options.direction_scan_points = -1;
  EXPECT_THROW(options.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace odomcal
