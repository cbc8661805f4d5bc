// The held translation z as a prior (translation_z_prior_sigma_m): on SE(3)
// odometry that informs z without determining it, z is estimated under the
// prior and x carries its uncertainty; held exactly, a wrong z biases x by
// the camera's height times the grade. Planar odometry does not depend on z:
// its result is the same with the prior as without.

#include "odomcal/datasets/simulation/climbing_road.h"
#include "odomcal/datasets/simulation/motion_simulator.h"
#include "odomcal/solver/calibrate.h"
#include "odomcal/solver/floor_translation_z.h"
#include "odomcal/tests/test_seed.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace odomcal {
namespace {

// An INS-grade relative tilt, z held at 0 (the camera is 1.65 m up).
CalibrationOptions InsOptions(double prior_sigma_m) {
  CalibrationOptions options;
  options.noise.odom_tilt_sigma_deg = 0.05;
  options.fixed_translation_z_m = 0.0;
  options.translation_z_prior_sigma_m = prior_sigma_m;
  return options;
}

bool XWithinThreeSigma(const CalibrationResult& result, const Rigid3d& truth) {
  return std::abs(result.odom_from_cam.translation.x() -
                  truth.translation.x()) <=
         3.0 * result.stddev_translation_xy_m.x();
}

// The drive of the measured failure: a camera 1.65 m up, a road whose grade
// varies within 0-2.5 deg. Held exactly at 0, z biases x far beyond its
// stated 3 sigma; under the default prior the data move z and x is covered.
TEST(CalibrateZPrior, ClimbingRoadXIsCoveredUnderThePrior) {
  const ClimbingRoadOptions road;
  const Rigid3d& truth = road.odom_from_cam;
  constexpr int kNumSeeds = 8;
  int held_covered = 0;
  int prior_covered = 0;
  for (int k = 0; k < kNumSeeds; ++k) {
    const uint64_t seed = TestSeed(5500) + k;
    SCOPED_TRACE("seed " + std::to_string(seed));
    const CalibrationOptions prior = InsOptions(1.0);
    const MotionPairs pairs = ClimbingRoadPairs(road, &prior.noise, seed);

    const CalibrationResult held = CalibrateOdomCam(pairs, InsOptions(0.0));
    ASSERT_EQ(held.status, CalibrationStatus::kSuccess) << held.message;
    // The motion does not determine z (the case under test).
    ASSERT_EQ(held.observability.translation_z, Determination::kHeld);
    EXPECT_EQ(held.odom_from_cam.translation.z(), 0.0);
    EXPECT_FALSE(held.translation_z_prior.used);
    held_covered += XWithinThreeSigma(held, truth);

    const CalibrationResult result = CalibrateOdomCam(pairs, prior);
    ASSERT_EQ(result.status, CalibrationStatus::kSuccess) << result.message;
    EXPECT_EQ(result.observability.translation_z, Determination::kHeld);
    EXPECT_EQ(UnobservableNames(result.observability).front(), "translation_z");
    const TranslationZPrior& z = result.translation_z_prior;
    ASSERT_TRUE(z.used);
    ASSERT_TRUE(z.moved_by_data);
    EXPECT_EQ(z.held_m, 0.0);
    EXPECT_EQ(z.prior_stddev_m, 1.0);
    // Informed, not determined: more than the 5 cm limit, less than the prior.
    EXPECT_GT(z.data_stddev_m, prior.max_translation_stddev_m);
    EXPECT_LT(z.data_stddev_m, 0.5);
    // Below the prior's; data_stddev_m is without the term of the scale's
    // wander (scale_drift_covariance.h), which joins after the prior.
    EXPECT_LT(z.stddev_m, z.prior_stddev_m);
    EXPECT_EQ(z.estimate_m, result.odom_from_cam.translation.z());
    EXPECT_LE(std::abs(z.estimate_m - truth.translation.z()), 3.0 * z.stddev_m);
    ASSERT_TRUE(result.covariance.has_value());
    EXPECT_EQ(result.covariance->rows(), 5 + 1 + 1);  // tz last
    EXPECT_NEAR(std::sqrt((*result.covariance)(6, 6)), z.stddev_m, 1e-15);
    // z's uncertainty is in x's.
    EXPECT_GT(result.stddev_translation_xy_m.x(),
              held.stddev_translation_xy_m.x());
    prior_covered += XWithinThreeSigma(result, truth);
  }
  EXPECT_LE(held_covered, 1) << "z held exactly is expected to bias x";
  EXPECT_EQ(prior_covered, kNumSeeds);
}

// Planar odometry carries no information on z and its residuals do not
// depend on it: with the prior, every result is as with z held exactly.
TEST(CalibrateZPrior, PlanarDriveIsUnchanged) {
  auto rng = SeededRng(5600);
  MotionSimulatorOptions simulation;
  simulation.num_pairs = 80;
  simulation.add_noise = true;
  const SimulatedMotions motions = SimulateMotions(simulation, &rng);
  CalibrationOptions held;
  held.fixed_translation_z_m = 0.3;
  held.translation_z_prior_sigma_m = 0.0;
  CalibrationOptions prior = held;
  prior.translation_z_prior_sigma_m = 1.0;
  const CalibrationResult a = CalibrateOdomCam(motions.pairs, held);
  const CalibrationResult b = CalibrateOdomCam(motions.pairs, prior);
  ASSERT_EQ(a.status, CalibrationStatus::kSuccess) << a.message;
  ASSERT_EQ(b.status, CalibrationStatus::kSuccess) << b.message;
  EXPECT_EQ(b.odom_from_cam.translation, a.odom_from_cam.translation);
  EXPECT_EQ(b.odom_from_cam.rotation.coeffs(),
            a.odom_from_cam.rotation.coeffs());
  EXPECT_EQ(b.metric_scales, a.metric_scales);
  ASSERT_TRUE(a.covariance && b.covariance);
  EXPECT_EQ(*b.covariance, *a.covariance);
  EXPECT_EQ(b.observability.translation_z, Determination::kHeld);
  const TranslationZPrior& z = b.translation_z_prior;
  EXPECT_TRUE(z.used);
  EXPECT_FALSE(z.moved_by_data);
  EXPECT_EQ(z.estimate_m, 0.3);
  EXPECT_EQ(z.stddev_m, 1.0);
  EXPECT_EQ(z.data_stddev_m, std::numeric_limits<double>::infinity());
}

// A fitted floor, 1.70 m under the camera, known to 1 mm; its height grows
// with the scale by 0.2 m per (m / unit).
FloorPlane FloorUnderTheCamera() {
  FloorPlane floor;
  floor.status = FloorPlaneStatus::kFitted;
  floor.camera_height_m = 1.70;
  floor.camera_height_stddev_m = 0.001;
  floor.height_per_scale = {0.2};
  return floor;
}

// A held z (6 x 6 covariance: rx, ry, rz, tx, ty, s_0).
CalibrationResult HeldZResult() {
  CalibrationResult result;
  result.has_estimate = true;
  result.odom_from_cam.translation = Eigen::Vector3d(1.2, 0.05, 0.0);
  result.metric_scales = {0.7};
  result.observability.metric_scales = {Determination::kEstimated};
  result.covariance_segments = {0};
  Eigen::MatrixXd covariance = Eigen::MatrixXd::Identity(6, 6) * 1e-6;
  covariance(5, 5) = 1e-4;
  covariance(5, 3) = covariance(3, 5) = 2e-6;
  result.covariance = covariance;
  result.stddev_metric_scales_rel = {0.01 / 0.7};
  return result;
}

// With a prior that tells nothing (uncorrelated, 100 m), the floor's update
// of a prior-moved z is the floor's z of a held one.
TEST(CalibrateZPrior, FloorUpdateOfAnUninformativePriorIsTheFloorsZ) {
  const FloorPlane floor = FloorUnderTheCamera();
  FloorPlaneOptions options;
  options.odometry_height_m = 0.05;
  CalibrationResult held = HeldZResult();
  ASSERT_EQ(SetTranslationZFromFloor(floor, options, 0.05, &held), "");
  CalibrationResult prior = HeldZResult();
  prior.translation_z_prior.used = true;
  prior.translation_z_prior.moved_by_data = true;
  Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(7, 7);
  covariance.topLeftCorner(6, 6) = *prior.covariance;
  covariance(6, 6) = 1e4;
  prior.covariance = covariance;
  ASSERT_EQ(SetTranslationZFromFloor(floor, options, 0.05, &prior), "");
  EXPECT_EQ(prior.observability.translation_z, Determination::kEstimated);
  EXPECT_EQ(prior.observability.translation_z_source,
            TranslationZSource::kFloorPlane);
  EXPECT_FALSE(prior.translation_z_prior.used);
  EXPECT_NEAR(prior.odom_from_cam.translation.z(), 1.65, 1e-6);
  ASSERT_EQ(prior.covariance->rows(), 7);
  EXPECT_LT((*prior.covariance - *held.covariance).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_NEAR(prior.stddev_translation_z_m, held.stddev_translation_z_m, 1e-9);
  EXPECT_NEAR(prior.odom_from_cam.translation.x(), 1.2, 1e-9);
}

// Correlated with z, x moves with it: z under its prior at 1.50 +- 0.10 m,
// x correlated with it (x = x_true + 0.02 (z - z_true)); the floor puts z at
// 1.65 m, and x moves by 0.02 * 0.15 = 3 mm, its variance from z gone.
TEST(CalibrateZPrior, FloorUpdateMovesXWithZ) {
  const FloorPlane floor = FloorUnderTheCamera();
  FloorPlaneOptions options;
  options.odometry_height_m = 0.05;
  CalibrationResult result = HeldZResult();
  result.translation_z_prior.used = true;
  result.translation_z_prior.moved_by_data = true;
  result.odom_from_cam.translation.z() = 1.50;
  Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(7, 7);
  covariance.topLeftCorner(6, 6) = *result.covariance;
  covariance(5, 3) = covariance(3, 5) = 0.0;
  const double z_variance = 0.01;
  covariance(6, 6) = z_variance;
  covariance(3, 6) = covariance(6, 3) = 0.02 * z_variance;
  covariance(3, 3) += 0.02 * 0.02 * z_variance;
  result.covariance = covariance;
  ASSERT_EQ(SetTranslationZFromFloor(floor, options, 0.05, &result), "");
  // The floor's z is 1.65 + 0.2 (s - 0.7) with s uncorrelated with z: the
  // update leaves s and moves z to the floor's within its 1 mm.
  EXPECT_NEAR(result.odom_from_cam.translation.z(), 1.65, 1e-3);
  EXPECT_NEAR(result.odom_from_cam.translation.x(),
              1.2 + 0.02 * (result.odom_from_cam.translation.z() - 1.50),
              1e-9);
  EXPECT_NEAR(result.stddev_translation_xy_m.x(), 1e-3, 1e-5);
}

}  // namespace
}  // namespace odomcal
