// CalibrateOdomCam on SE(3) odometry (an INS or VIO over non-planar ground):
// the odometry rotations tilt, their axes are not all parallel, and the
// translation z of the extrinsic is estimated with its standard deviation.

#include "odomcal/datasets/simulation/motion_simulator.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/calibrate.h"
#include "odomcal/solver/hand_eye_residual.h"
#include "odomcal/tests/test_seed.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace odomcal {
namespace {

constexpr double kMetricScale = 0.7;  // metres per reconstruction unit

Eigen::Quaterniond FromRollPitchYaw(double roll, double pitch, double yaw) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()));
}

// A mount with a non-zero height: the camera looks ahead, slightly turned.
Rigid3d TrueOdomFromCam() {
  return Rigid3d(
      FromRollPitchYaw(-92.0 * kDegToRad, 1.5 * kDegToRad, -87.0 * kDegToRad),
      Eigen::Vector3d(0.42, -0.13, 0.35));
}

// Keyframe poses origin_from_odom of a drive over rough ground: 0.5 m steps
// along the vehicle's x axis, yaw increments in [-30, 30] deg, roll and pitch
// in [-tilt, tilt] per keyframe (the height follows the pitch). tilt 0 is a
// planar drive.
std::vector<Rigid3d> RoughGroundDrive(int num_keyframes,
                                      double tilt_deg,
                                      std::mt19937_64* rng) {
  std::uniform_real_distribution<double> turn(-30.0, 30.0);
  std::uniform_real_distribution<double> tilt(-tilt_deg, tilt_deg);
  std::vector<Rigid3d> poses;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double yaw = 0.0;
  for (int k = 0; k < num_keyframes; ++k) {
    const Eigen::Quaterniond rotation =
        FromRollPitchYaw(tilt(*rng) * kDegToRad, tilt(*rng) * kDegToRad, yaw);
    poses.emplace_back(rotation, position);
    position += rotation * Eigen::Vector3d(0.5, 0.0, 0.0);
    yaw += turn(*rng) * kDegToRad;
  }
  return poses;
}

// A measurement drawn from `covariance` (order [rotation, translation]):
// rotation Exp(n) * R, translation t + n_t, as the solver models it.
Rigid3d Measure(const Rigid3d& motion,
                const MotionCovariance& covariance,
                std::mt19937_64* rng) {
  std::normal_distribution<double> unit(0.0, 1.0);
  Eigen::Matrix<double, 6, 1> draw;
  for (int k = 0; k < 6; ++k) draw(k) = unit(*rng);
  const Eigen::Matrix<double, 6, 1> n = covariance.llt().matrixL() * draw;
  return Rigid3d((ExpRotation(n.head<3>()) * motion.rotation).normalized(),
                 motion.translation + n.tail<3>());
}

// Motion pairs of consecutive keyframes; noise from `noise` when given.
MotionPairs PairsOf(const std::vector<Rigid3d>& origin_from_odom,
                    const NoiseModel* noise,
                    std::mt19937_64* rng) {
  MotionPairs pairs;
  for (size_t k = 0; k + 1 < origin_from_odom.size(); ++k) {
    MotionPair pair;
    pair.odom_i_from_odom_j =
        Inverse(origin_from_odom[k]) * origin_from_odom[k + 1];
    pair.cam_i_from_cam_j = CameraMotionFromOdometryMotion(
        pair.odom_i_from_odom_j, TrueOdomFromCam(), kMetricScale);
    if (noise) {
      // The true steps: the pair is exact here.
      const StepSize step = MeasuredStep(pair);
      const MotionCovariance odom = OdometryCovariance(pair, *noise, step);
      const MotionCovariance cam = CameraCovariance(pair, *noise, step);
      pair.odom_i_from_odom_j = Measure(pair.odom_i_from_odom_j, odom, rng);
      pair.cam_i_from_cam_j = Measure(pair.cam_i_from_cam_j, cam, rng);
    }
    pair.stamp_i_ns = static_cast<int64_t>(k) * 500000000;
    pair.stamp_j_ns = pair.stamp_i_ns + 500000000;
    pairs.push_back(pair);
  }
  return pairs;
}

// An INS-grade relative tilt; z held at 0 until the data determine it.
CalibrationOptions Se3Options() {
  CalibrationOptions options;
  options.noise.odom_tilt_sigma_deg = 0.05;
  options.fixed_translation_z_m = 0.0;
  return options;
}

std::vector<std::string> Unobservable(const CalibrationResult& result) {
  return UnobservableNames(result.observability);
}

TEST(CalibrateSe3Odometry, NoiseFreeRecoversAllSixDegreesOfFreedom) {
  auto rng = SeededRng(151);
  const MotionPairs pairs =
      PairsOf(RoughGroundDrive(80, 4.0, &rng), nullptr, &rng);
  const CalibrationResult result = CalibrateOdomCam(pairs, Se3Options());
  ASSERT_EQ(result.status, CalibrationStatus::kSuccess) << result.message;
  EXPECT_EQ(result.observability.translation_z, Determination::kEstimated);
  EXPECT_TRUE(Unobservable(result).empty());
  const Rigid3d truth = TrueOdomFromCam();
  EXPECT_LT(
      RotationAngle(result.odom_from_cam.rotation.conjugate() * truth.rotation),
      1e-6);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(result.odom_from_cam.translation(k), truth.translation(k), 1e-6)
        << "axis " << k;
  }
  EXPECT_NEAR(result.metric_scales[0] / kMetricScale, 1.0, 1e-6);
  ASSERT_TRUE(result.covariance.has_value());
  EXPECT_EQ(result.covariance->rows(), 5 + 1 + 1);  // tz last
  EXPECT_GT(result.stddev_translation_z_m, 0.0);
  EXPECT_NEAR(result.stddev_translation_z_m,
              std::sqrt((*result.covariance)(6, 6)),
              1e-15);
}

// Noise drawn from the noise model the solver assumes: the truth must lie
// within the stated 3 sigma for rotation (per axis), x, y, z and the scale.
TEST(CalibrateSe3Odometry, NoisyDrivesAreWithinThreeSigma) {
  const CalibrationOptions options = Se3Options();
  const Rigid3d truth = TrueOdomFromCam();
  for (uint64_t seed = 1; seed <= 8; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    auto rng = SeededRng(1510 + seed);
    const MotionPairs pairs =
        PairsOf(RoughGroundDrive(120, 4.0, &rng), &options.noise, &rng);
    const CalibrationResult result = CalibrateOdomCam(pairs, options);
    ASSERT_EQ(result.status, CalibrationStatus::kSuccess) << result.message;
    ASSERT_EQ(result.observability.translation_z, Determination::kEstimated);
    ASSERT_TRUE(result.covariance.has_value());
    // Left perturbation: R_true = Exp(phi) R_hat.
    const Eigen::Vector3d phi =
        LogRotation(truth.rotation * result.odom_from_cam.rotation.conjugate());
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE(std::abs(phi(k)),
                3.0 * result.stddev_rotation_axes_deg(k) * kDegToRad)
          << "rotation axis " << k;
    }
    const Eigen::Vector3d error =
        result.odom_from_cam.translation - truth.translation;
    EXPECT_LE(std::abs(error.x()), 3.0 * result.stddev_translation_xy_m.x());
    EXPECT_LE(std::abs(error.y()), 3.0 * result.stddev_translation_xy_m.y());
    EXPECT_LE(std::abs(error.z()), 3.0 * result.stddev_translation_z_m)
        << "z " << result.odom_from_cam.translation.z() << " +- "
        << result.stddev_translation_z_m;
    EXPECT_LE(std::abs(result.metric_scales[0] / kMetricScale - 1.0),
              3.0 * result.stddev_metric_scales_rel[0]);
  }
}

// The same drive with planar odometry: z is held, exactly as before.
TEST(CalibrateSe3Odometry, PlanarOdometryHoldsZ) {
  auto rng = SeededRng(152);
  CalibrationOptions options = Se3Options();
  options.fixed_translation_z_m = TrueOdomFromCam().translation.z();
  const MotionPairs pairs =
      PairsOf(RoughGroundDrive(80, 0.0, &rng), nullptr, &rng);
  const CalibrationResult result = CalibrateOdomCam(pairs, options);
  ASSERT_EQ(result.status, CalibrationStatus::kSuccess) << result.message;
  EXPECT_EQ(result.observability.translation_z, Determination::kHeld);
  EXPECT_EQ(Unobservable(result), std::vector<std::string>{"translation_z"});
  EXPECT_EQ(result.odom_from_cam.translation.z(),
            options.fixed_translation_z_m);
  ASSERT_TRUE(result.covariance.has_value());
  EXPECT_EQ(result.covariance->rows(), 5 + 1);
  EXPECT_EQ(result.stddev_translation_z_m, 0.0);
}

// Tilted rotations whose axes are all parallel (odometry frame mounted
// tilted on a planar drive) leave p along that axis free: z is held, decided
// from the information, not from the tilt alone.
TEST(CalibrateSe3Odometry, ParallelRotationAxesHoldZ) {
  auto rng = SeededRng(153);
  const Rigid3d planar_from_odom(FromRollPitchYaw(4.0 * kDegToRad, 0.0, 0.0),
                                 Eigen::Vector3d::Zero());
  std::vector<Rigid3d> poses = RoughGroundDrive(80, 0.0, &rng);
  for (Rigid3d& pose : poses) pose = pose * planar_from_odom;
  CalibrationOptions options = Se3Options();
  options.use_ransac = false;
  const CalibrationResult result =
      CalibrateOdomCam(PairsOf(poses, nullptr, &rng), options);
  EXPECT_EQ(result.observability.translation_z, Determination::kHeld)
      << result.message;
  EXPECT_EQ(result.odom_from_cam.translation.z(), 0.0);
  EXPECT_EQ(Unobservable(result).front(), "translation_z");
}

}  // namespace
}  // namespace odomcal
