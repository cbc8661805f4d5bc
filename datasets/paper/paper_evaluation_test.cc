#include "odomcal/datasets/paper/paper_evaluation.h"

#include "odomcal/datasets/paper/paper_sweeps.h"
#include "odomcal/tests/test_seed.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace odomcal {
namespace {

// The paper's first claim (ALSP-L-B ~ GT-B) as a regression bound.
constexpr double kBatchRelativeTolerance = 0.02;

TEST(RunSweepPoint, AlspLBMatchesGtBAndAlspLBeatsCm) {
  const PaperSimulationOptions simulation =
      ApplySweepValue(NominalPaperSimulation(CameraNoiseMode::kParametric),
                      "rotation_noise",
                      0.1);
  EvaluationOptions options;
  const SweepPointResult point =
      RunSweepPoint(simulation, options, "test", 0, 0.1, 300, 2, TestSeed(320));
  const MethodSummary& alsp_l_b =
      point[EvaluationMethod::kAlspLengthPreservingB];
  const MethodSummary& gt_b = point[EvaluationMethod::kGtB];
  const MethodSummary& alsp_l = point[EvaluationMethod::kAlspLengthPreserving];
  const MethodSummary& cm = point[EvaluationMethod::kCm];
  EXPECT_EQ(alsp_l_b.num_failures, 0);
  EXPECT_EQ(gt_b.num_failures, 0);
  EXPECT_NEAR(alsp_l_b.rmse_rotation_deg / gt_b.rmse_rotation_deg,
              1.0,
              kBatchRelativeTolerance);
  EXPECT_NEAR(alsp_l_b.rmse_translation_m / gt_b.rmse_translation_m,
              1.0,
              kBatchRelativeTolerance);
  EXPECT_NEAR(alsp_l_b.rmse_scale_rel / gt_b.rmse_scale_rel,
              1.0,
              kBatchRelativeTolerance);
  EXPECT_LT(alsp_l.rmse_rotation_deg, cm.rmse_rotation_deg);
  EXPECT_LT(alsp_l.rmse_translation_m, cm.rmse_translation_m);
  EXPECT_LT(alsp_l.rmse_scale_rel, cm.rmse_scale_rel);
  // The orthogonal projection reproduces ALS.
  EXPECT_NEAR(point[EvaluationMethod::kAlspOrthogonal].rmse_rotation_deg,
              point[EvaluationMethod::kAls].rmse_rotation_deg,
              1e-9);
  // A consistent estimator: divergences only by chance (< 1.6 % expected).
  EXPECT_LT(gt_b.divergence_rate, 0.05);
  EXPECT_FALSE(std::isnan(gt_b.divergence_rate));
  EXPECT_TRUE(std::isnan(alsp_l.divergence_rate));
}

// The B methods' inlier test leaves out gross motions and keeps good ones.
TEST(RunSweepPoint, BatchInlierTestLeavesOutOutlierMotions) {
  PaperSimulationOptions simulation =
      NominalPaperSimulation(CameraNoiseMode::kParametric);
  simulation.num_motions = 40;
  simulation.outlier_fraction = 0.1;
  EvaluationOptions all_motions;
  all_motions.batch_refinement = BatchRefinement::kPaper;
  EvaluationOptions inlier_test;
  inlier_test.batch_refinement = BatchRefinement::kInlierRounds;
  const SweepPointResult plain = RunSweepPoint(
      simulation, all_motions, "test", 0, 0.1, 60, 2, TestSeed(321));
  const SweepPointResult gated = RunSweepPoint(
      simulation, inlier_test, "test", 0, 0.1, 60, 2, TestSeed(321));
  for (const EvaluationMethod method :
       {EvaluationMethod::kAlspLengthPreservingB, EvaluationMethod::kGtB}) {
    SCOPED_TRACE(ToString(method));
    EXPECT_EQ(plain[method].num_failures, 0);
    EXPECT_EQ(gated[method].num_failures, 0);
    EXPECT_EQ(plain[method].motions_used, 1.0);
    // Each motion is an outlier with probability 0.1, so 90 % of the motions
    // are good (SD of the mean over 60 trials of 40: 0.6 points); the test
    // keeps 99.9 % of them and no outlier (18-90 deg of extra rotation).
    EXPECT_GT(gated[method].motions_used, 0.87);
    EXPECT_LT(gated[method].motions_used, 0.93);
    // The outliers dominate the paper's batch.
    EXPECT_LT(gated[method].rmse_rotation_deg,
              0.5 * plain[method].rmse_rotation_deg);
    EXPECT_LT(gated[method].divergence_rate, 0.1);
  }
  EXPECT_TRUE(std::isnan(gated[EvaluationMethod::kAls].motions_used));

  simulation.outlier_fraction = 0.0;
  const SweepPointResult clean = RunSweepPoint(
      simulation, inlier_test, "test", 0, 0.1, 60, 2, TestSeed(322));
  for (const EvaluationMethod method :
       {EvaluationMethod::kAlspLengthPreservingB, EvaluationMethod::kGtB}) {
    SCOPED_TRACE(ToString(method));
    EXPECT_GT(clean[method].motions_used, 0.98);
  }
}

// Five motions (the fewest of the motion-count sweep), one in five an
// outlier: a round that would keep fewer than half of them is not trusted,
// no trial fails, and outliers are left out.
TEST(RunSweepPoint, BatchInlierRoundsWithFewMotions) {
  PaperSimulationOptions simulation =
      NominalPaperSimulation(CameraNoiseMode::kParametric);
  simulation.num_motions = 5;
  simulation.outlier_fraction = 0.2;
  const SweepPointResult point = RunSweepPoint(
      simulation, EvaluationOptions(), "test", 0, 0.1, 60, 2, TestSeed(323));
  for (const EvaluationMethod method :
       {EvaluationMethod::kAlspLengthPreservingB, EvaluationMethod::kGtB}) {
    SCOPED_TRACE(ToString(method));
    EXPECT_EQ(point[method].num_failures, 0);
    // Some draws leave too few good motions for a regular information.
    EXPECT_GE(point[method].num_with_covariance, 55);
    // At least 3 of 5 motions in every trial.
    EXPECT_GE(point[method].motions_used, 0.6);
    EXPECT_LT(point[method].motions_used, 1.0);
  }
}

bool SameError(const MethodError& a, const MethodError& b) {
  return a.failed == b.failed && a.rotation_deg == b.rotation_deg &&
         a.translation_m == b.translation_m && a.scale_rel == b.scale_rel &&
         a.has_covariance == b.has_covariance && a.diverged == b.diverged;
}

TEST(RunTrials, IndependentOfTheThreadCount) {
  PaperSimulationOptions simulation =
      NominalPaperSimulation(CameraNoiseMode::kLandmarks);
  simulation.two_view_minimal_samples = 0;  // speed; deterministic either way
  EvaluationOptions options;
  options.cm_ransac_iterations = 50;
  int calls = 0;
  const std::vector<TrialResult> one = RunTrials(
      simulation, options, "pixel_noise", 3, 12, 1, 7, [&calls](int, int) {
        ++calls;
      });
  const std::vector<TrialResult> two =
      RunTrials(simulation, options, "pixel_noise", 3, 12, 2, 7);
  EXPECT_EQ(calls, 12);
  ASSERT_EQ(one.size(), two.size());
  for (size_t t = 0; t < one.size(); ++t) {
    for (int m = 0; m < kNumEvaluationMethods; ++m) {
      EXPECT_TRUE(SameError(one[t].methods[m], two[t].methods[m]))
          << "trial " << t << " method " << m;
    }
  }
}

// The inlier rounds test each motion on `inlier_test_pairs` when given and
// weight it with `pairs`: a wrong motion whose weighting covariance is wide
// enough to pass is still dropped when its test covariance is its own.
TEST(RefineBatch, InlierRoundsTestOnTheTestPairs) {
  PaperSimulationOptions options =
      NominalPaperSimulation(CameraNoiseMode::kParametric);
  auto rng = SeededRng(331);
  PaperSimulation simulation = SimulatePaperMotions(options, &rng);
  ASSERT_EQ(simulation.pairs.size(), 20u);
  const MotionPairs test_pairs = simulation.pairs;
  MotionPair& wrong = simulation.pairs[7];
  wrong.cam_i_from_cam_j.rotation =
      ExpRotation(Eigen::Vector3d(0.0, 0.3, 0.0)) *
      wrong.cam_i_from_cam_j.rotation;
  *wrong.cam_covariance *= 1e4;
  MotionPairs wrong_test_pairs = test_pairs;
  wrong_test_pairs[7].cam_i_from_cam_j = wrong.cam_i_from_cam_j;
  CalibrationOptions refine;
  refine.fixed_translation_z_m = simulation.odom_from_cam.translation.z();
  const auto used = [&](const MotionPairs* test) {
    const BatchRefined refined = RefineBatch(simulation.pairs,
                                             simulation.odom_from_cam,
                                             simulation.metric_scales,
                                             refine,
                                             BatchRefinement::kInlierRounds,
                                             test);
    EXPECT_TRUE(refined.refinement.usable);
    return std::count(refined.used.begin(), refined.used.end(), 7);
  };
  EXPECT_EQ(used(nullptr), 1);
  EXPECT_EQ(used(&wrong_test_pairs), 0);
}

// GT-B (the truth as start, the paper's batch) on one large parametric
// simulation whose stated covariances are divided by `understatement`.
double VarianceFactorOfLargeSimulation(double understatement) {
  PaperSimulationOptions options =
      NominalPaperSimulation(CameraNoiseMode::kParametric);
  options.num_motions = 1000;
  auto rng = SeededRng(330);
  PaperSimulation simulation = SimulatePaperMotions(options, &rng);
  for (MotionPair& pair : simulation.pairs) {
    *pair.odom_covariance /= understatement;
    *pair.cam_covariance /= understatement;
  }
  CalibrationOptions refine;
  refine.fixed_translation_z_m = simulation.odom_from_cam.translation.z();
  const BatchRefined refined = RefineBatch(simulation.pairs,
                                           simulation.odom_from_cam,
                                           simulation.metric_scales,
                                           refine,
                                           BatchRefinement::kPaper);
  EXPECT_TRUE(refined.refinement.usable);
  return PosteriorVarianceFactor(refined.refinement,
                                 static_cast<int>(refined.used.size()));
}

// 1000 motions, 5994 degrees of freedom: the factor's own standard deviation
// is 2 %, so 10 % is a wide margin.
TEST(PosteriorVarianceFactor, NearOneWhenTheMotionsScatterAsStated) {
  EXPECT_NEAR(VarianceFactorOfLargeSimulation(1.0), 1.0, 0.1);
}

TEST(PosteriorVarianceFactor, RecoversCovariancesStatedFourTimesTooSmall) {
  EXPECT_NEAR(VarianceFactorOfLargeSimulation(4.0) / 4.0, 1.0, 0.1);
}

TEST(PosteriorVarianceFactor, NotANumberWithoutDegreesOfFreedom) {
  RefinementResult refined;
  refined.final_cost = 1.0;
  refined.information_segments = {0};
  EXPECT_TRUE(std::isnan(PosteriorVarianceFactor(refined, 1)));
  EXPECT_NEAR(PosteriorVarianceFactor(refined, 2), 2.0 / 6.0, 1e-12);
}

TEST(TrialSeed, DependsOnEveryInput) {
  const uint64_t seed = TrialSeed(1, "a", 0, 0);
  EXPECT_EQ(seed, TrialSeed(1, "a", 0, 0));
  EXPECT_NE(seed, TrialSeed(2, "a", 0, 0));
  EXPECT_NE(seed, TrialSeed(1, "b", 0, 0));
  EXPECT_NE(seed, TrialSeed(1, "a", 1, 0));
  EXPECT_NE(seed, TrialSeed(1, "a", 0, 1));
}

TEST(SummarizeTrials, FailuresAreCountedNotAveraged) {
  // One motion cannot determine anything: every method fails.
  PaperSimulationOptions simulation =
      NominalPaperSimulation(CameraNoiseMode::kParametric);
  simulation.num_motions = 1;
  const SweepPointResult point =
      RunSweepPoint(simulation, EvaluationOptions(), "test", 0, 1.0, 4, 1, 1);
  const MethodSummary& alsp_l = point[EvaluationMethod::kAlspLengthPreserving];
  EXPECT_EQ(alsp_l.num_failures, 4);
  EXPECT_TRUE(std::isnan(alsp_l.rmse_rotation_deg));
  EXPECT_EQ(point[EvaluationMethod::kCm].num_failures, 4);
  EXPECT_EQ(point[EvaluationMethod::kCmB].num_failures, 4);
}

TEST(ApplySweepValue, SetsTheSweptParameter) {
  const PaperSimulationOptions nominal =
      NominalPaperSimulation(CameraNoiseMode::kLandmarks);
  EXPECT_EQ(ApplySweepValue(nominal, "rotation_noise", 0.3).odom_yaw_sigma_rad,
            0.3);
  EXPECT_EQ(ApplySweepValue(nominal, "num_motions", 50).num_motions, 50);
  EXPECT_EQ(ApplySweepValue(nominal, "pixel_noise", 2).pixel_sigma, 2.0);
  EXPECT_THROW(ApplySweepValue(nominal, "nope", 1), std::invalid_argument);
  EXPECT_THROW(FindPaperSweep("nope"), std::invalid_argument);
  EXPECT_EQ(PaperSweeps().size(), 4u);
}

}  // namespace
}  // namespace odomcal
