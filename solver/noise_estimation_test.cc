#include "odomcal/solver/noise_estimation.h"

#include "odomcal/datasets/simulation/motion_simulator.h"
#include "odomcal/solver/calibrate.h"
#include "odomcal/solver/hand_eye_refine.h"
#include "odomcal/tests/test_seed.h"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace odomcal {
namespace {

constexpr NoiseGroup kGroups[] = {NoiseGroup::kOdometryRotation,
                                  NoiseGroup::kOdometryTranslation,
                                  NoiseGroup::kCameraRotation,
                                  NoiseGroup::kCameraTranslation};

// Pairs simulated with the prior noise scaled by `true_factors`.
// With `zero_lever_arm` the extrinsic has no translation, so that camera
// and odometry steps have the same length.
SimulatedMotions Simulate(const NoiseModel& prior,
                          const NoiseFactors& true_factors,
                          int num_pairs,
                          uint64_t seed,
                          bool zero_lever_arm = false) {
  MotionSimulatorOptions simulation;
  simulation.num_pairs = num_pairs;
  simulation.add_noise = true;
  simulation.noise = ScaleNoise(prior, true_factors);
  std::mt19937_64 rng(seed);
  Rigid3d odom_from_cam = RandomOdomFromCam(&rng);
  if (zero_lever_arm) odom_from_cam.translation.setZero();
  return SimulateMotions(simulation, odom_from_cam, {0.5}, &rng);
}

CalibrationOptions OptionsFor(const SimulatedMotions& truth,
                              const NoiseModel& prior) {
  CalibrationOptions options;
  options.noise = prior;
  options.fixed_translation_z_m = truth.odom_from_cam.translation.z();
  return options;
}

// A given noise with one component per group (no proportional parts): the
// groups are separable with enough pairs.
NoiseModel OneComponentPerGroup() {
  NoiseModel prior;
  prior.odom_yaw_sigma_deg = 0.3;
  prior.odom_yaw_sigma_rel = 0.0;
  prior.odom_translation_sigma_m = 0.01;
  prior.odom_translation_sigma_rel = 0.0;
  prior.cam_rotation_sigma_deg = 0.1;
  prior.cam_translation_sigma_rel = 0.02;
  return prior;
}

// Noise 2x and 0.5x the given model (standard deviations), separable groups:
// each group's ratio recovered within 10 % through the whole pipeline.
TEST(NoiseEstimation, RecoversPerGroupNoiseThroughTheCalibration) {
  const uint64_t seed = TestSeed(141);
  SCOPED_TRACE("seed " + std::to_string(seed));
  const NoiseModel prior = OneComponentPerGroup();
  const NoiseFactors truth_factors = {4.0, 0.25, 0.25, 4.0};
  const SimulatedMotions truth = Simulate(prior, truth_factors, 1500, seed);
  const CalibrationResult result =
      CalibrateOdomCam(truth.pairs, OptionsFor(truth, prior));
  ASSERT_EQ(result.status, CalibrationStatus::kSuccess) << result.message;
  ASSERT_TRUE(result.noise_estimate.has_value());
  const NoiseEstimate& noise = *result.noise_estimate;
  SCOPED_TRACE(NoiseSummary(noise));
  for (const NoiseGroup group : kGroups) {
    const int g = static_cast<int>(group);
    EXPECT_TRUE(noise.estimated[g]) << ToString(group);
    EXPECT_EQ(noise.tie[g], g) << ToString(group);
    EXPECT_NEAR(noise.SigmaRatio(group) / std::sqrt(truth_factors[g]), 1.0, 0.1)
        << ToString(group);
  }
  EXPECT_NEAR(result.diagnostics.reduced_chi_square, 1.0, 0.1);
  // The estimated model is the given one with scaled standard deviations.
  EXPECT_NEAR(noise.noise.odom_yaw_sigma_deg,
              prior.odom_yaw_sigma_deg * noise.SigmaRatio(kGroups[0]),
              1e-12);
  EXPECT_NE(NoiseSummary(noise).find("noise estimated from "),
            std::string::npos);
}

// Odometry and camera translation noise both proportional to the step
// length, and (no lever arm) the steps equally long: their contributions have
// the same shape (sized by one modelled step), so they are tied and share
// one factor, which matches the common true ratio. (With a lever arm of a few
// centimetres, the camera steps differ enough in length for 800 pairs to
// separate them.)
TEST(NoiseEstimation, TiesGroupsTheDataCannotSeparate) {
  const uint64_t seed = TestSeed(142);
  SCOPED_TRACE("seed " + std::to_string(seed));
  NoiseModel prior;
  prior.odom_translation_sigma_m = 1e-7;  // must be > 0
  prior.odom_translation_sigma_rel = 0.02;
  prior.cam_translation_sigma_rel = 0.02;
  const NoiseFactors truth_factors = {1.0, 2.25, 1.0, 2.25};
  const SimulatedMotions truth =
      Simulate(prior, truth_factors, 800, seed, /*zero_lever_arm=*/true);
  const CalibrationResult result =
      CalibrateOdomCam(truth.pairs, OptionsFor(truth, prior));
  ASSERT_EQ(result.status, CalibrationStatus::kSuccess) << result.message;
  ASSERT_TRUE(result.noise_estimate.has_value());
  const NoiseEstimate& noise = *result.noise_estimate;
  const std::string summary = NoiseSummary(noise);
  SCOPED_TRACE(summary);
  EXPECT_TRUE(noise.Tied(NoiseGroup::kOdometryTranslation,
                         NoiseGroup::kCameraTranslation));
  EXPECT_FALSE(
      noise.Tied(NoiseGroup::kOdometryRotation, NoiseGroup::kCameraRotation));
  EXPECT_NEAR(noise.SigmaRatio(NoiseGroup::kCameraTranslation), 1.5, 0.15);
  EXPECT_NEAR(noise.SigmaRatio(NoiseGroup::kOdometryTranslation), 1.5, 0.15);
  // The components: odometry translation proportional to the length and
  // camera translation across the motion share one factor.
  const auto component = [](NoiseComponent c) { return static_cast<int>(c); };
  EXPECT_EQ(
      noise.component_tie[component(
          NoiseComponent::kOdometryTranslationProportional)],
      noise.component_tie[component(NoiseComponent::kCameraTranslationAcross)]);
  // The summary names them in one tie.
  const size_t tie = summary.find("(tied: not separable) x1.");
  ASSERT_NE(tie, std::string::npos);
  const size_t odometry = summary.find("odometry translation (proportional)");
  const size_t camera = summary.find("camera translation (across the motion)");
  EXPECT_LT(odometry, tie);
  EXPECT_LT(camera, tie);
  EXPECT_EQ(summary.find("(tied", odometry), tie);
}

// Two pairs: 12 residuals, 6 parameters. No group, not even all tied
// together, is determined to within kMaxRelativeStddev (one common factor
// from 6 degrees of freedom: sqrt(2 / 6) = 0.58): the given noise is kept,
// and the summary says so.
TEST(NoiseEstimation, KeepsTheGivenNoiseWithTooFewPairs) {
  const uint64_t seed = TestSeed(143);
  SCOPED_TRACE("seed " + std::to_string(seed));
  const NoiseModel prior;
  const SimulatedMotions truth = Simulate(prior, {4.0, 4.0, 4.0, 4.0}, 2, seed);
  const NoiseEstimate noise = EstimateNoise(truth.pairs,
                                            {0, 1},
                                            truth.odom_from_cam,
                                            truth.metric_scales,
                                            OptionsFor(truth, prior));
  for (const NoiseGroup group : kGroups) {
    EXPECT_FALSE(noise.estimated[static_cast<int>(group)]) << ToString(group);
    EXPECT_EQ(noise.SigmaRatio(group), 1.0);
  }
  EXPECT_EQ(NoiseSummary(noise),
            "noise estimated from 2 pairs (standard deviations relative to "
            "the given noise): none determined; kept as given: odometry "
            "yaw (constant), odometry yaw (proportional), odometry "
            "translation (constant), odometry translation (proportional), "
            "camera rotation, camera translation (across the motion), camera "
            "translation (along the motion) (not determined by these "
            "pairs)");
}

bool IsEstimable(int component) {
  return component != static_cast<int>(NoiseComponent::kOdometryTilt);
}

// Exact pairs. With the data alone (the default) every level runs to its
// floor, 0.1x the given standard deviation, instead of claiming zero noise:
// held there and named, without a misfit widening (the pairs fit better than
// the given noise, not worse). With a prior of w pseudo-observations a level
// stays near w / (r + w) of the given variance (r its share of the
// redundancy), above the floor.
TEST(NoiseEstimation, ExactDataStopAtTheFloorOrStayAboveItWithAPrior) {
  std::mt19937_64 rng(TestSeed(146));
  MotionSimulatorOptions simulation;
  simulation.num_pairs = 100;
  const SimulatedMotions truth = SimulateMotions(simulation, &rng);
  const NoiseModel prior;
  std::vector<int> used(truth.pairs.size());
  for (size_t i = 0; i < used.size(); ++i) used[i] = static_cast<int>(i);
  CalibrationOptions options = OptionsFor(truth, prior);
  const NoiseEstimate alone = EstimateNoise(
      truth.pairs, used, truth.odom_from_cam, truth.metric_scales, options);
  const std::string summary = NoiseSummary(alone);
  SCOPED_TRACE(summary);
  for (const NoiseGroup group : kGroups) {
    EXPECT_NEAR(alone.SigmaRatio(group), 0.1, 1e-12) << ToString(group);
  }
  for (int c = 0; c < kNumNoiseComponents; ++c) {
    if (!alone.component_present[c] || !IsEstimable(c)) continue;
    EXPECT_EQ(alone.component_bound[c], NoiseBound::kFloor)
        << ToString(static_cast<NoiseComponent>(c));
  }
  EXPECT_EQ(alone.misfit_widening, 1.0);
  EXPECT_NE(summary.find("; held at 0.1x, the data ask for less: odometry "
                         "yaw (constant)"),
            std::string::npos);

  options.noise_prior_weight = 4.0;
  const NoiseEstimate with_prior = EstimateNoise(
      truth.pairs, used, truth.odom_from_cam, truth.metric_scales, options);
  SCOPED_TRACE(NoiseSummary(with_prior));
  for (int c = 0; c < kNumNoiseComponents; ++c) {
    if (!with_prior.component_present[c] || !IsEstimable(c)) continue;
    const NoiseComponent component = static_cast<NoiseComponent>(c);
    EXPECT_EQ(with_prior.component_bound[c], NoiseBound::kNone)
        << ToString(component);
    EXPECT_TRUE(with_prior.component_estimated[c]) << ToString(component);
    EXPECT_GT(with_prior.SigmaRatio(component), 0.1) << ToString(component);
    EXPECT_LT(with_prior.SigmaRatio(component), 0.5) << ToString(component);
  }
}

// Odometry yaw noise 20x the given (as a systematic yaw error that the
// noise takes up would look): its level runs to the 10x ceiling, is kept at
// the given noise and named, the translation groups are still estimated,
// and the covariance is widened by the misfit that the kept level leaves.
// (The camera rotation, the other noise of the rotation residual, may take
// up that misfit next and be named as well.)
TEST(NoiseEstimation, ALevelAtTheCeilingIsKeptNamedAndWidensTheCovariance) {
  const uint64_t seed = TestSeed(148);
  SCOPED_TRACE("seed " + std::to_string(seed));
  const NoiseModel prior = OneComponentPerGroup();
  const SimulatedMotions truth =
      Simulate(prior, {400.0, 1.0, 1.0, 1.0}, 500, seed);
  std::vector<int> used(truth.pairs.size());
  for (size_t i = 0; i < used.size(); ++i) used[i] = static_cast<int>(i);
  const NoiseEstimate noise = EstimateNoise(truth.pairs,
                                            used,
                                            truth.odom_from_cam,
                                            truth.metric_scales,
                                            OptionsFor(truth, prior));
  const std::string summary = NoiseSummary(noise);
  SCOPED_TRACE(summary);
  const int yaw = static_cast<int>(NoiseComponent::kOdometryYawConstant);
  EXPECT_EQ(noise.component_bound[yaw], NoiseBound::kCeiling);
  EXPECT_FALSE(noise.component_estimated[yaw]);
  EXPECT_EQ(noise.SigmaRatio(NoiseComponent::kOdometryYawConstant), 1.0);
  for (const NoiseGroup group :
       {NoiseGroup::kOdometryTranslation, NoiseGroup::kCameraTranslation}) {
    EXPECT_TRUE(noise.estimated[static_cast<int>(group)]) << ToString(group);
  }
  // One residual of six carries 400x its given variance: chi-square over
  // redundancy near (400 + 5) / 6 before the others absorb some of it.
  EXPECT_GT(noise.misfit_widening, 3.0);
  EXPECT_NE(summary.find("kept as given, the data ask for over 10x: odometry "
                         "yaw (constant)"),
            std::string::npos);
  EXPECT_NE(summary.find("(an error the noise model does not describe"),
            std::string::npos);
  EXPECT_NE(summary.find("standard deviations widened x"), std::string::npos);
}

// The weights are estimated, not known: the covariance is widened for that
// (Kenward-Roger). The widening never narrows,
// and the summary names it where it matters. (In the paper protocol, 20
// pairs with a mis-shaped given noise, it is 5 % on average, up to 50 %:
// docs/statistics.md.)
TEST(NoiseEstimation, WidensTheCovarianceForTheEstimatedNoise) {
  const uint64_t seed = TestSeed(147);
  SCOPED_TRACE("seed " + std::to_string(seed));
  const NoiseModel prior = OneComponentPerGroup();
  std::vector<double> widenings;
  for (const int num_pairs : {20, 1500}) {
    SCOPED_TRACE(std::to_string(num_pairs) + " pairs");
    const SimulatedMotions truth =
        Simulate(prior, {4.0, 0.25, 0.25, 4.0}, num_pairs, seed);
    CalibrationOptions options = OptionsFor(truth, prior);
    std::vector<int> used(truth.pairs.size());
    for (size_t i = 0; i < used.size(); ++i) used[i] = static_cast<int>(i);
    const NoiseEstimate noise = EstimateNoise(
        truth.pairs, used, truth.odom_from_cam, truth.metric_scales, options);
    ASSERT_GT(noise.kenward_roger_term.rows(), 0) << NoiseSummary(noise);
    SCOPED_TRACE(NoiseSummary(noise));
    options.noise = noise.noise;
    std::vector<int> segments;
    const Eigen::MatrixXd information =
        HandEyeInformation(ScaleCovariances(truth.pairs, noise),
                           used,
                           truth.odom_from_cam,
                           truth.metric_scales,
                           options,
                           &segments);
    double widening = 0.0;
    const Eigen::MatrixXd widened =
        WidenForEstimatedNoise(information, segments, noise, &widening);
    const Eigen::MatrixXd added = widened.inverse() - information.inverse();
    const double smallest =
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(added)
            .eigenvalues()
            .minCoeff();
    EXPECT_GE(smallest, -1e-9 * information.inverse().norm());
    double largest_ratio = 1.0;
    for (int k = 0; k < information.rows(); ++k) {
      largest_ratio = std::max(
          largest_ratio,
          std::sqrt(widened.inverse()(k, k) / information.inverse()(k, k)));
    }
    EXPECT_NEAR(widening, largest_ratio, 1e-9);
    widenings.push_back(widening);
  }
  // Some with 20 pairs; negligible with 1500 (the term is of order 1 /
  // pairs, although more components are separated there).
  EXPECT_GT(widenings[0], 1.0);
  EXPECT_LT(widenings[1], 1.005);
  // Named in the summary from 0.5 %.
  NoiseEstimate reported;
  reported.stddev_widening = 1.06;
  EXPECT_NE(NoiseSummary(reported).find(
                "; standard deviations widened by up to 6.0 % for this "
                "estimate's own uncertainty (Kenward-Roger)"),
            std::string::npos);
  reported.stddev_widening = 1.004;
  EXPECT_EQ(NoiseSummary(reported).find("Kenward"), std::string::npos);
}

TEST(NoiseEstimation, ScalesThePairsOwnCovariances) {
  MotionPair pair;
  MotionCovariance covariance = MotionCovariance::Identity();
  covariance(0, 3) = covariance(3, 0) = 0.5;
  pair.odom_covariance = covariance;
  pair.cam_covariance = covariance;
  const MotionPairs scaled =
      ScaleCovariances({pair}, NoiseFactors{4.0, 9.0, 0.25, 1.0});
  EXPECT_DOUBLE_EQ((*scaled[0].odom_covariance)(0, 0), 4.0);
  EXPECT_DOUBLE_EQ((*scaled[0].odom_covariance)(4, 4), 9.0);
  EXPECT_DOUBLE_EQ((*scaled[0].odom_covariance)(0, 3), 0.5 * 6.0);
  EXPECT_DOUBLE_EQ((*scaled[0].cam_covariance)(2, 2), 0.25);
  EXPECT_DOUBLE_EQ((*scaled[0].cam_covariance)(5, 5), 1.0);
}

}  // namespace
}  // namespace odomcal
