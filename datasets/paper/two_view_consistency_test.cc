#include "odomcal/datasets/paper/two_view_consistency.h"

#include "odomcal/datasets/paper/paper_sweeps.h"
#include "odomcal/datasets/paper/two_view_pose.h"
#include "odomcal/solver/angles.h"
#include "odomcal/tests/test_seed.h"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <optional>
#include <random>
#include <vector>

namespace odomcal {
namespace {

TEST(SummarizeTwoViewErrors, QuantilesAndGrossRateOfKnownSamples) {
  TwoViewErrors errors;
  for (int k = 1; k <= 100; ++k) {
    errors.nees.push_back(k);
    errors.direction_error_deg.push_back(k <= 7 ? 20.0 : 1.0);
  }
  const TwoViewConsistency summary = SummarizeTwoViewErrors(errors);
  EXPECT_EQ(summary.num_motions, 100);
  EXPECT_EQ(summary.nees_median, 50.0);
  EXPECT_EQ(summary.nees_quantile_90, 90.0);
  EXPECT_EQ(summary.nees_quantile_99, 99.0);
  EXPECT_EQ(summary.nees_max, 100.0);
  EXPECT_DOUBLE_EQ(summary.gross_error_rate, 0.07);
}

// One motion with a known covariance and a known error: NEES by hand.
TEST(AddTwoViewErrors, WhitensWithTheFiveObservableDimensions) {
  PaperSimulation simulation;
  MotionPair truth;
  truth.cam_i_from_cam_j =
      Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.0, 0.0, 2.0));
  MotionPair measured = truth;
  // Rotation error 0.01 rad about x; translation 0.02 along y at length 2.
  measured.cam_i_from_cam_j.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(-0.01, Eigen::Vector3d::UnitX()));
  measured.cam_i_from_cam_j.translation =
      Eigen::Vector3d(0.0, 0.02, std::sqrt(4.0 - 0.02 * 0.02));
  MotionCovariance covariance = MotionCovariance::Zero();
  covariance.diagonal() << 1e-4, 1e-4, 1e-4, 4e-4, 4e-4, 0.0;
  measured.cam_covariance = covariance;
  simulation.pairs = {measured};
  simulation.true_pairs = {truth};
  simulation.is_outlier = {0};
  TwoViewErrors errors;
  AddTwoViewErrors(simulation, &errors);
  ASSERT_EQ(errors.nees.size(), 1u);
  // (0.01^2 / 1e-4) + (0.02^2 / 4e-4), up to the second-order z error.
  EXPECT_NEAR(errors.nees[0], 2.0, 1e-3);
  EXPECT_NEAR(errors.direction_error_deg[0], std::asin(0.01) * kRadToDeg, 1e-9);
}

// The two-view estimators compared on the nominal landmark protocol (1 px,
// 12 landmarks 0.5-5 m deep, f = 400 px, 20 motions per simulation): the
// same motions and observations for each. Numbers of larger runs:
// docs/paper_reproduction.md, "Two-view estimates" (benchmarks/
// paper_studies two_view_large_set).
struct TwoViewEstimator {
  const char* name;
  bool multi_start;
  int direction_scan_points;
};
const TwoViewEstimator kEightPointOnly = {"8-point only", false, 0};
const TwoViewEstimator kEveryStartNoScan = {
    "every start, no direction scan", true, 0};
const TwoViewEstimator kDefaultEstimator = {
    "every start and the direction scan (default)",
    true,
    TwoViewOptions().direction_scan_points};

// The two-view consistency of `num_simulations` nominal landmark
// simulations of 20 motions.
TwoViewConsistency NominalTwoViewConsistency(const TwoViewEstimator& estimator,
                                             int num_simulations,
                                             uint64_t seed) {
  PaperSimulationOptions options =
      NominalPaperSimulation(CameraNoiseMode::kLandmarks);
  options.two_view_multi_start = estimator.multi_start;
  options.two_view_direction_scan_points = estimator.direction_scan_points;
  auto rng = SeededRng(seed);
  TwoViewErrors errors;
  for (int k = 0; k < num_simulations; ++k) {
    AddTwoViewErrors(SimulatePaperMotions(options, &rng), &errors);
  }
  return SummarizeTwoViewErrors(errors);
}

TEST(TwoViewConsistency, EveryStartAndTheScanShortenTheTail) {
  std::vector<TwoViewConsistency> summaries;
  for (const TwoViewEstimator& estimator :
       {kEightPointOnly, kEveryStartNoScan, kDefaultEstimator}) {
    summaries.push_back(NominalTwoViewConsistency(estimator, 30, 700));
    const TwoViewConsistency& c = summaries.back();
    std::cout << estimator.name << ": " << c.num_motions
              << " motions, NEES median " << c.nees_median
              << ", 99th percentile " << c.nees_quantile_99 << ", gross "
              << 100.0 * c.gross_error_rate << " %\n";
  }
  const TwoViewConsistency& eight_point = summaries[0];
  const TwoViewConsistency& no_scan = summaries[1];
  const TwoViewConsistency& scanned = summaries[2];
  ASSERT_GT(scanned.num_motions, 570);
  // The bulk follows chi-square(5) (median 4.35).
  EXPECT_NEAR(scanned.nees_median, kChiSquare5Median, 0.8);
  EXPECT_LE(no_scan.gross_error_rate, eight_point.gross_error_rate);
  EXPECT_LT(no_scan.nees_quantile_99, 0.6 * eight_point.nees_quantile_99);
  // The scan changes covariances only (so not the gross errors) and brings
  // the tail within issue 17's target, 2x chi-square's 99th percentile.
  EXPECT_EQ(scanned.gross_error_rate, no_scan.gross_error_rate);
  EXPECT_LT(scanned.nees_quantile_99, 0.8 * no_scan.nees_quantile_99);
  EXPECT_LT(scanned.nees_quantile_99, 2.0 * kChiSquare5Quantile99);
}

// The winner's cost is never above the 8-point start's, and on some motions
// another start reaches a lower minimum; the covariance is the bundle
// adjustment's at the winner, widened (never narrowed) where other minima
// fit the data almost as well.
TEST(EstimateTwoViewPose, EveryStartNeverEndsAboveTheEightPointStart) {
  PaperSimulationOptions options =
      NominalPaperSimulation(CameraNoiseMode::kParametric);
  auto rng = SeededRng(701);
  std::normal_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<double> depth(0.5, 5.0);
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
  const double sigma = 1.0 / 400.0;
  int num_lower = 0;
  int num_widened = 0;
  int num_motions = 0;
  for (int s = 0; s < 25; ++s) {
    const PaperSimulation simulation = SimulatePaperMotions(options, &rng);
    for (const MotionPair& pair : simulation.true_pairs) {
      Rigid3d metric = pair.cam_i_from_cam_j;
      metric.translation *= simulation.metric_scales[pair.segment];
      const Rigid3d cam_j_from_cam_i = Inverse(metric);
      std::vector<Eigen::Vector2d> u_i, u_j;
      while (u_i.size() < 12) {
        const double z = depth(rng);
        const double x = coordinate(rng);
        const double y = coordinate(rng);
        const Eigen::Vector3d p_j =
            cam_j_from_cam_i * Eigen::Vector3d(x * z, y * z, z);
        if (p_j.z() < 0.5) continue;
        Eigen::Vector4d n;
        for (int c = 0; c < 4; ++c) n(c) = sigma * unit(rng);
        u_i.emplace_back(x + n(0), y + n(1));
        u_j.emplace_back(p_j.x() / p_j.z() + n(2), p_j.y() / p_j.z() + n(3));
      }
      TwoViewOptions two_view;
      two_view.multi_start = false;
      const TwoViewEstimate eight_point =
          EstimateTwoViewPose(u_i, u_j, two_view);
      two_view.multi_start = true;
      two_view.num_minimal_samples = 0;  // speed: 8-point and 5-point starts
      const TwoViewEstimate every_start =
          EstimateTwoViewPose(u_i, u_j, two_view);
      if (!eight_point.success || !every_start.success) continue;
      ++num_motions;
      EXPECT_LE(every_start.final_cost, eight_point.final_cost + 1e-9);
      if (every_start.final_cost < eight_point.final_cost - 1e-3) ++num_lower;
      // The other minima only widen the covariance of the best one.
      const std::optional<MotionCovariance> at_best =
          TwoViewPoseCovarianceAt(u_i,
                                  u_j,
                                  every_start.cam_i_from_cam_j,
                                  every_start.points_in_cam_i,
                                  two_view);
      ASSERT_TRUE(at_best.has_value());
      const MotionCovariance widening = every_start.covariance - *at_best;
      const double scale = at_best->trace();
      EXPECT_GT(Eigen::SelfAdjointEigenSolver<MotionCovariance>(widening)
                    .eigenvalues()
                    .minCoeff(),
                -1e-9 * scale);
      if (every_start.num_other_minima > 0 ||
          every_start.num_direction_cells > 0) {
        ++num_widened;
        EXPECT_GT(widening.trace(), 1e-6 * scale);
      } else {
        EXPECT_LT(widening.cwiseAbs().maxCoeff(), 1e-12 * scale);
      }
    }
  }
  EXPECT_GT(num_motions, 450);
  EXPECT_GT(num_lower, 0);
  EXPECT_GT(num_widened, 0);
}

}  // namespace
}  // namespace odomcal
