#include "odomcal/solver/hand_eye_linear.h"

#include "odomcal/datasets/simulation/motion_simulator.h"
#include "odomcal/solver/angles.h"
#include "odomcal/tests/test_seed.h"

#include <gtest/gtest.h>

#include <cmath>

namespace odomcal {
namespace {

// Noise-free recovery tolerances (issue #2): rotation 1e-6 deg, x/y 1e-9 m,
// scale 1e-9 relative.
constexpr double kRotationToleranceDeg = 1e-6;
constexpr double kTranslationToleranceM = 1e-9;
constexpr double kScaleToleranceRel = 1e-9;

double RotationErrorDeg(const Eigen::Quaterniond& a,
                        const Eigen::Quaterniond& b) {
  return RotationAngle(a.conjugate() * b) * 180.0 / kPi;
}

void ExpectExactRecovery(const SimulatedMotions& truth,
                         const LinearEstimate& estimate) {
  ASSERT_TRUE(estimate.success) << estimate.failure;
  EXPECT_LT(RotationErrorDeg(truth.odom_from_cam.rotation,
                             estimate.odom_from_cam.rotation),
            kRotationToleranceDeg);
  EXPECT_NEAR(estimate.odom_from_cam.translation.x(),
              truth.odom_from_cam.translation.x(),
              kTranslationToleranceM);
  EXPECT_NEAR(estimate.odom_from_cam.translation.y(),
              truth.odom_from_cam.translation.y(),
              kTranslationToleranceM);
  ASSERT_EQ(estimate.metric_scales.size(), truth.metric_scales.size());
  for (size_t k = 0; k < truth.metric_scales.size(); ++k) {
    EXPECT_NEAR(estimate.metric_scales[k] / truth.metric_scales[k],
                1.0,
                kScaleToleranceRel)
        << "segment " << k;
  }
}

MotionSimulatorOptions ExactOptions(int num_pairs, int num_segments) {
  MotionSimulatorOptions options;
  options.num_pairs = num_pairs;
  options.num_segments = num_segments;
  return options;
}

TEST(QuaternionProductMatrices, MatchEigenHamiltonProduct) {
  auto rng = SeededRng(1);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Quaterniond p = RandomOdomFromCam(&rng).rotation;
    const Eigen::Quaterniond q = RandomOdomFromCam(&rng).rotation;
    const Eigen::Quaterniond pq = p * q;
    const Eigen::Vector4d expected(pq.w(), pq.x(), pq.y(), pq.z());
    const Eigen::Vector4d p4(p.w(), p.x(), p.y(), p.z());
    const Eigen::Vector4d q4(q.w(), q.x(), q.y(), q.z());
    EXPECT_LT((QuaternionLeftMatrix(p) * q4 - expected).norm(), 1e-15);
    EXPECT_LT((QuaternionRightMatrix(q) * p4 - expected).norm(), 1e-15);
  }
}

TEST(EstimateOdomFromCamLinear, ExactOnHundredsOfRandomExtrinsics) {
  const uint64_t seed = TestSeed(2);
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  for (int trial = 0; trial < 300; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const SimulatedMotions truth =
        SimulateMotions(ExactOptions(20, 1 + trial % 3), &rng);
    ExpectExactRecovery(truth, EstimateOdomFromCamLinear(truth.pairs, {}));
  }
}

TEST(EstimateOdomFromCamLinear, ExactForMinimalAndLargeProblems) {
  auto rng = SeededRng(3);
  for (const int num_pairs : {2, 3, 1000}) {
    SCOPED_TRACE("pairs " + std::to_string(num_pairs));
    for (int trial = 0; trial < 20; ++trial) {
      const SimulatedMotions truth =
          SimulateMotions(ExactOptions(num_pairs, 1), &rng);
      ExpectExactRecovery(truth, EstimateOdomFromCamLinear(truth.pairs, {}));
    }
  }
}

// Camera mounts that stress the Z-Y-Z decomposition and the sign handling.
TEST(EstimateOdomFromCamLinear, ExactForSpecialMounts) {
  auto rng = SeededRng(4);
  const Eigen::Vector3d t(0.05, -0.07, 0.3);
  const std::vector<std::pair<std::string, Eigen::Quaterniond>> mounts = {
      {"identity", Eigen::Quaterniond::Identity()},
      // Looking straight down / up: camera z parallel to odometry z, the
      // gimbal case where the constraint of eq. (19) vanishes.
      {"down",
       Eigen::Quaterniond(Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitX()))},
      {"up",
       Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()))},
      {"forward",  // x_cam = -y_odom, y_cam = -z_odom, z_cam = x_odom
       Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5)},
      {"forward_rolled_90",
       Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5) *
           Eigen::Quaterniond(
               Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitZ()))},
      {"near_pi",
       Eigen::Quaterniond(Eigen::AngleAxisd(
           kPi - 1e-7, Eigen::Vector3d(1, 2, 3).normalized()))},
      {"exactly_pi_about_y",
       Eigen::Quaterniond(Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitY()))},
      {"tiny",
       Eigen::Quaterniond(
           Eigen::AngleAxisd(1e-5, Eigen::Vector3d(0, 1, 1).normalized()))},
  };
  for (const auto& [name, rotation] : mounts) {
    SCOPED_TRACE(name);
    const std::vector<double> scales = {0.7};
    const SimulatedMotions truth = SimulateMotions(
        ExactOptions(30, 1), Rigid3d(rotation.normalized(), t), scales, &rng);
    const LinearEstimate estimate = EstimateOdomFromCamLinear(truth.pairs, {});
    ExpectExactRecovery(truth, estimate);
  }
}

TEST(EstimateOdomFromCamLinear, GimbalCaseIsDetected) {
  auto rng = SeededRng(5);
  const SimulatedMotions truth = SimulateMotions(
      ExactOptions(10, 1),
      Rigid3d(
          Eigen::Quaterniond(Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitX())),
          Eigen::Vector3d(0.1, 0.2, 0.0)),
      {1.3},
      &rng);
  const LinearEstimate estimate = EstimateOdomFromCamLinear(truth.pairs, {});
  EXPECT_TRUE(estimate.rotation_step_gimbal);
  EXPECT_EQ(estimate.num_constraint_roots, 1);
}

TEST(EstimateOdomFromCamLinear, InvariantToQuaternionSigns) {
  auto rng = SeededRng(6);
  SimulatedMotions truth = SimulateMotions(ExactOptions(25, 2), &rng);
  for (size_t i = 0; i < truth.pairs.size(); i += 2) {
    truth.pairs[i].cam_i_from_cam_j.rotation.coeffs() *= -1.0;
  }
  for (size_t i = 0; i < truth.pairs.size(); i += 3) {
    truth.pairs[i].odom_i_from_odom_j.rotation.coeffs() *= -1.0;
  }
  ExpectExactRecovery(truth, EstimateOdomFromCamLinear(truth.pairs, {}));
}

// The two roots of w x = y z differ by a rotation of pi about z, which step 2
// absorbs into alpha: both give the same final rotation.
TEST(SolveRotationYZ, BothRootsGiveTheSameExtrinsic) {
  auto rng = SeededRng(7);
  for (const bool noisy : {false, true}) {
    for (int trial = 0; trial < 50; ++trial) {
      MotionSimulatorOptions options = ExactOptions(40, 1);
      options.add_noise = noisy;
      const SimulatedMotions truth = SimulateMotions(options, &rng);
      std::vector<int> all(truth.pairs.size());
      for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
      LinearEstimate step1;
      const auto roots = SolveRotationYZ(truth.pairs, all, &step1);
      ASSERT_EQ(roots.size(), 2u);
      const double yaw_between = RotationAngle(roots[0] * roots[1].conjugate());
      EXPECT_NEAR(yaw_between, kPi, 1e-6);
      const Eigen::Vector3d axis =
          LogRotation(roots[0] * roots[1].conjugate()).normalized();
      EXPECT_NEAR(std::abs(axis.z()), 1.0, 1e-6);
      LinearEstimate first = step1, second = step1;
      ASSERT_TRUE(
          SolveYawTranslationScale(truth.pairs, all, roots[0], {}, &first));
      ASSERT_TRUE(
          SolveYawTranslationScale(truth.pairs, all, roots[1], {}, &second));
      EXPECT_LT(RotationErrorDeg(first.odom_from_cam.rotation,
                                 second.odom_from_cam.rotation),
                1e-9);
      EXPECT_NEAR(first.step2_cost,
                  second.step2_cost,
                  1e-12 * (1.0 + first.step2_cost));
    }
  }
}

// The orthogonal projection leaves the first two components of R(q_yz) t
// unchanged, so it reproduces ALS exactly; the length-preserving one differs.
TEST(EstimateOdomFromCamLinear, OrthogonalProjectionEqualsAls) {
  auto rng = SeededRng(8);
  MotionSimulatorOptions options = ExactOptions(40, 1);
  options.add_noise = true;
  options.noise.cam_translation_sigma_rel = 0.05;
  const SimulatedMotions truth = SimulateMotions(options, &rng);
  LinearOptions als, orthogonal, length_preserving;
  als.method = LinearMethod::kAls;
  orthogonal.alsp_projection = PlaneProjection::kOrthogonal;
  length_preserving.alsp_projection = PlaneProjection::kLengthPreserving;
  const LinearEstimate a = EstimateOdomFromCamLinear(truth.pairs, als);
  const LinearEstimate b = EstimateOdomFromCamLinear(truth.pairs, orthogonal);
  const LinearEstimate c =
      EstimateOdomFromCamLinear(truth.pairs, length_preserving);
  ASSERT_TRUE(a.success && b.success && c.success);
  EXPECT_LT(
      RotationErrorDeg(a.odom_from_cam.rotation, b.odom_from_cam.rotation),
      1e-12);
  EXPECT_LT((a.odom_from_cam.translation - b.odom_from_cam.translation).norm(),
            1e-12);
  EXPECT_GT((a.odom_from_cam.translation - c.odom_from_cam.translation).norm(),
            1e-9);
}

// With one segment the multi-segment path (profile over alpha + Gauss-Newton)
// must agree with the paper's linear least squares; checked by splitting one
// segment's pairs into two segments with equal true scale.
TEST(EstimateOdomFromCamLinear, SegmentsSolvedJointly) {
  auto rng = SeededRng(9);
  MotionSimulatorOptions options = ExactOptions(60, 1);
  options.add_noise = true;
  const SimulatedMotions one = SimulateMotions(options, &rng);
  const LinearEstimate joint = EstimateOdomFromCamLinear(one.pairs, {});
  // Same data, labelled as 3 segments: scales become independent, so the
  // fit can only get better, and stays close.
  MotionPairs split = one.pairs;
  for (size_t i = 0; i < split.size(); ++i) split[i].segment = i % 3;
  const LinearEstimate separate = EstimateOdomFromCamLinear(split, {});
  ASSERT_TRUE(joint.success && separate.success);
  EXPECT_LE(separate.step2_cost, joint.step2_cost * (1.0 + 1e-9));
  EXPECT_EQ(separate.metric_scales.size(), 3u);
  for (const double s : separate.metric_scales) {
    EXPECT_NEAR(s / joint.metric_scales[0], 1.0, 0.05);
  }
}

TEST(EstimateOdomFromCamLinear, RefusesNoRotation) {
  auto rng = SeededRng(10);
  MotionSimulatorOptions options = ExactOptions(20, 1);
  options.min_yaw_rad = options.max_yaw_rad = 0.0;
  const SimulatedMotions truth = SimulateMotions(options, &rng);
  const LinearEstimate estimate = EstimateOdomFromCamLinear(truth.pairs, {});
  EXPECT_FALSE(estimate.success);
  EXPECT_NE(estimate.failure.find("no rotation"), std::string::npos);
}

TEST(EstimateOdomFromCamLinear, RefusesFewerThanTwoPairs) {
  auto rng = SeededRng(11);
  const SimulatedMotions truth = SimulateMotions(ExactOptions(1, 1), &rng);
  EXPECT_FALSE(EstimateOdomFromCamLinear(truth.pairs, {}).success);
}

}  // namespace
}  // namespace odomcal
