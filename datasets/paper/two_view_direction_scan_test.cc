#include "odomcal/datasets/paper/two_view_direction_scan.h"

#include "odomcal/datasets/paper/two_view_pose.h"
#include "odomcal/tests/test_seed.h"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace odomcal {
namespace {

struct Views {
  Rigid3d cam_i_from_cam_j;  // unit translation
  std::vector<Eigen::Vector2d> u_i, u_j;
};

// 12 points at depths [min_depth, 5] m within +-45 degrees, seen from two
// poses `baseline_m` apart with up to 60 degrees of rotation, 1 px noise at
// f = 400 px.
Views RandomViews(double baseline_m,
                  double min_depth_m,
                  double pixel_sigma,
                  std::mt19937_64* rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::uniform_real_distribution<double> depth(min_depth_m, 5.0);
  Eigen::Vector3d axis, direction;
  for (int c = 0; c < 3; ++c) axis(c) = normal(*rng);
  for (int c = 0; c < 3; ++c) direction(c) = normal(*rng);
  const double angle = 0.5 * (uniform(*rng) + 1.0);
  Views views;
  views.cam_i_from_cam_j =
      Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized())),
              direction.normalized());
  Rigid3d metric = views.cam_i_from_cam_j;
  metric.translation *= baseline_m;
  const Rigid3d cam_j_from_cam_i = Inverse(metric);
  const double sigma = pixel_sigma / 400.0;
  while (views.u_i.size() < 12) {
    const double z = depth(*rng);
    const double x = uniform(*rng);
    const double y = uniform(*rng);
    const Eigen::Vector3d p_j =
        cam_j_from_cam_i * Eigen::Vector3d(x * z, y * z, z);
    if (p_j.z() < 0.5) continue;
    Eigen::Vector4d n;
    for (int c = 0; c < 4; ++c) n(c) = sigma * normal(*rng);
    views.u_i.emplace_back(x + n(0), y + n(1));
    views.u_j.emplace_back(p_j.x() / p_j.z() + n(2), p_j.y() / p_j.z() + n(3));
  }
  return views;
}

// A well-determined direction (0.5 m against points 1-5 m deep, 0.1 px) is
// left alone: its cost is quadratic over many grid cells.
TEST(ScanTranslationDirection, LeavesAWellDeterminedDirectionAlone) {
  auto rng = SeededRng(721);
  for (int trial = 0; trial < 20; ++trial) {
    const Views views = RandomViews(0.5, 1.0, 0.1, &rng);
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
    const Views views = RandomViews(0.02, 1.0, 1.0, &rng);
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
