#include "odomcal/datasets/paper/paper_simulation.h"

#include "odomcal/tests/test_seed.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace odomcal {
namespace {

// Sample standard deviations over N draws are within ~3/sqrt(2N) of the
// truth with high probability; N = 4000 gives 3.4 %.
constexpr int kNumMotions = 4000;
constexpr double kSigmaTolerance = 0.05;  // relative

double Rms(const std::vector<double>& values) {
  double sum = 0.0;
  for (const double v : values) sum += v * v;
  return std::sqrt(sum / values.size());
}

PaperSimulationOptions ManyParametricMotions() {
  PaperSimulationOptions options;
  options.num_motions = kNumMotions;
  options.camera_noise = CameraNoiseMode::kParametric;
  options.odom_yaw_sigma_rad = 0.1;
  options.odom_translation_sigma_rel = 0.05;
  options.cam_rotation_sigma_rad = 0.01;
  options.cam_direction_sigma_rad = 0.03;
  return options;
}

TEST(SimulatePaperMotions, OdometryNoiseMatchesParameters) {
  auto rng = SeededRng(310);
  const PaperSimulationOptions options = ManyParametricMotions();
  const PaperSimulation simulation = SimulatePaperMotions(options, &rng);
  ASSERT_EQ(simulation.pairs.size(), static_cast<size_t>(kNumMotions));
  std::vector<double> yaw_errors, translation_errors;
  for (size_t i = 0; i < simulation.pairs.size(); ++i) {
    const Rigid3d& measured = simulation.pairs[i].odom_i_from_odom_j;
    const Rigid3d& truth = simulation.true_pairs[i].odom_i_from_odom_j;
    const Eigen::Vector3d phi =
        LogRotation(measured.rotation * truth.rotation.conjugate());
    EXPECT_NEAR(phi.head<2>().norm(), 0.0, 1e-12);  // planar
    yaw_errors.push_back(phi.z());
    const Eigen::Vector3d dt = measured.translation - truth.translation;
    EXPECT_EQ(dt.z(), 0.0);
    const double length = truth.translation.norm();
    translation_errors.push_back(dt.x() / length);
    translation_errors.push_back(dt.y() / length);
    // The attached covariance is the one applied (plus the tiny floor).
    const MotionCovariance& c = *simulation.pairs[i].odom_covariance;
    EXPECT_NEAR(c(2, 2), 0.1 * 0.1, 1e-10);
    EXPECT_NEAR(c(3, 3), std::pow(0.05 * length, 2), 1e-10);
    EXPECT_GT(c(0, 0), 0.0);  // floor keeps it invertible
  }
  EXPECT_NEAR(Rms(yaw_errors) / 0.1, 1.0, kSigmaTolerance);
  EXPECT_NEAR(Rms(translation_errors) / 0.05, 1.0, kSigmaTolerance);
}

TEST(SimulatePaperMotions, ParametricCameraNoiseMatchesParameters) {
  auto rng = SeededRng(311);
  const PaperSimulationOptions options = ManyParametricMotions();
  const PaperSimulation simulation = SimulatePaperMotions(options, &rng);
  std::vector<double> rotation_errors, direction_errors;
  for (size_t i = 0; i < simulation.pairs.size(); ++i) {
    const Rigid3d& measured = simulation.pairs[i].cam_i_from_cam_j;
    const Rigid3d& truth = simulation.true_pairs[i].cam_i_from_cam_j;
    const Eigen::Vector3d phi =
        LogRotation(measured.rotation * truth.rotation.conjugate());
    for (int k = 0; k < 3; ++k) rotation_errors.push_back(phi(k));
    EXPECT_NEAR(measured.translation.norm(),
                truth.translation.norm(),
                1e-12 * truth.translation.norm());
    // Angle between directions: |m| with m ~ N(0, sigma_d^2 I2), so
    // E[angle^2] = 2 sigma_d^2; report it per tangent axis.
    const double angle =
        std::atan2(measured.translation.cross(truth.translation).norm(),
                   measured.translation.dot(truth.translation));
    direction_errors.push_back(angle / std::sqrt(2.0));
  }
  EXPECT_NEAR(Rms(rotation_errors) / 0.01, 1.0, kSigmaTolerance);
  EXPECT_NEAR(Rms(direction_errors) / 0.03, 1.0, kSigmaTolerance);
}

TEST(SimulatePaperMotions, LandmarksWithoutNoiseGiveExactMotions) {
  auto rng = SeededRng(312);
  PaperSimulationOptions options;
  options.num_motions = 30;
  options.camera_noise = CameraNoiseMode::kLandmarks;
  options.pixel_sigma = 0.0;
  options.odom_yaw_sigma_rad = 0.0;
  options.odom_translation_sigma_rel = 0.0;
  const PaperSimulation simulation = SimulatePaperMotions(options, &rng);
  EXPECT_EQ(simulation.num_two_view_failures, 0);
  ASSERT_EQ(simulation.pairs.size(), 30u);
  for (size_t i = 0; i < simulation.pairs.size(); ++i) {
    const Rigid3d& measured = simulation.pairs[i].cam_i_from_cam_j;
    const Rigid3d& truth = simulation.true_pairs[i].cam_i_from_cam_j;
    EXPECT_LT(RotationAngle(measured.rotation.conjugate() * truth.rotation),
              1e-7);
    EXPECT_LT((measured.translation - truth.translation).norm(),
              1e-7 * truth.translation.norm());
  }
}

TEST(SimulatePaperMotions, SegmentsOutliersAndDeterminism) {
  PaperSimulationOptions options;
  options.num_motions = 40;
  options.num_segments = 2;
  options.outlier_fraction = 0.25;
  options.camera_noise = CameraNoiseMode::kParametric;
  std::mt19937_64 rng_a(TestSeed(313)), rng_b(TestSeed(313));
  const PaperSimulation a = SimulatePaperMotions(options, &rng_a);
  const PaperSimulation b = SimulatePaperMotions(options, &rng_b);
  ASSERT_EQ(a.metric_scales.size(), 2u);
  EXPECT_NE(a.metric_scales[0], a.metric_scales[1]);
  EXPECT_EQ(a.pairs.front().segment, 0);
  EXPECT_EQ(a.pairs.back().segment, 1);
  int outliers = 0;
  for (size_t i = 0; i < a.pairs.size(); ++i) {
    outliers += a.is_outlier[i];
    EXPECT_EQ(a.pairs[i].cam_i_from_cam_j.translation,
              b.pairs[i].cam_i_from_cam_j.translation);
  }
  EXPECT_GT(outliers, 0);
  EXPECT_LT(outliers, 40);
  options.num_segments = 0;
  EXPECT_THROW(SimulatePaperMotions(options, &rng_a), std::invalid_argument);
}

}  // namespace
}  // namespace odomcal
