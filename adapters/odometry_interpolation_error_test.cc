#include "odomcal/adapters/odometry_interpolation_error.h"

#include "odomcal/adapters/association.h"
#include "odomcal/solver/angles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace odomcal {
namespace {

constexpr int64_t kBaseNs = 1700000000000000000;

// A unicycle at 0.5 m/s that drives straight until t_turn_s and then turns
// at 0.8 rad/s: the pose at t, integrated in closed form.
Rigid3d TurningPose(double t, double t_turn_s) {
  const double v = 0.5, w = 0.8;
  if (t <= t_turn_s) {
    return Rigid3d(Eigen::Quaterniond::Identity(),
                   Eigen::Vector3d(v * t, 0.0, 0.0));
  }
  const double s = t - t_turn_s;
  const double r = v / w;
  return Rigid3d(YawRotation(w * s),
                 Eigen::Vector3d(v * t_turn_s + r * std::sin(w * s),
                                 r * (1.0 - std::cos(w * s)),
                                 0.0));
}

Trajectory SampleTurning(double rate_hz, double duration_s, double t_turn_s) {
  Trajectory log;
  log.planar = true;
  for (int i = 0; i * (1.0 / rate_hz) <= duration_s; ++i) {
    const double t = i / rate_hz;
    log.poses.push_back(
        {kBaseNs + std::llround(t * 1e9), TurningPose(t, t_turn_s)});
  }
  return log;
}

double YawOf(const Rigid3d& pose) { return LogRotation(pose.rotation).z(); }

TEST(OdometryInterpolationCovariance, ZeroAtConstantVelocity) {
  // Turning from the start: the geodesic is exact, every interval has the
  // same yaw rate and body-frame velocity.
  const Trajectory log = SampleTurning(4.0, 5.0, -1.0);
  for (double t = 0.3; t < 4.6; t += 0.1) {
    const Eigen::Matrix3d covariance =
        OdometryInterpolationCovariance(log, kBaseNs + std::llround(t * 1e9));
    EXPECT_LT(std::sqrt(covariance(0, 0)), 1e-12) << t;
    EXPECT_LT(std::sqrt(covariance(1, 1)), 1e-12) << t;
  }
  // On a sample: nothing interpolated; continued at constant velocity just
  // before the first sample: exact; far outside the log: nothing.
  EXPECT_TRUE(
      OdometryInterpolationCovariance(log, log.poses[3].stamp_ns).isZero(0.0));
  EXPECT_LT(std::sqrt(OdometryInterpolationCovariance(log, kBaseNs - 1)(0, 0)),
            1e-12);
  EXPECT_TRUE(
      OdometryInterpolationCovariance(log, kBaseNs - 1000000000).isZero(0.0));
}

// A turn that starts in the last interval: the pose continued a tenth of an
// interval beyond the log is off, and the stated covariance covers it.
TEST(OdometryInterpolationCovariance, CoversTheErrorJustBeyondTheEnd) {
  const double t_turn_s = 2.9;  // 4 Hz samples up to 3.0 s
  const Trajectory log = SampleTurning(4.0, 3.0, t_turn_s);
  const int64_t last_ns = log.poses.back().stamp_ns;
  const int64_t stamp = last_ns + 25000000;  // a tenth of 0.25 s
  const auto continued = InterpolateOdometry(log, stamp, 1.0, nullptr);
  ASSERT_TRUE(continued.has_value());
  const Rigid3d truth =
      TurningPose(static_cast<double>(stamp - kBaseNs) / 1e9, t_turn_s);
  const double yaw_error =
      std::abs(WrapAngle(YawOf(*continued) - YawOf(truth)));
  const Eigen::Matrix3d covariance =
      OdometryInterpolationCovariance(log, stamp);
  EXPECT_GT(yaw_error, 1e-3);
  EXPECT_LE(yaw_error, 3.0 * std::sqrt(covariance(0, 0)));
  EXPECT_LE((continued->translation - truth.translation).norm(),
            3.0 * std::sqrt(covariance(1, 1)));
}

TEST(OdometryInterpolationCovariance, CoversTheErrorWhereTheTurnStarts) {
  // 4 Hz odometry; the turn starts between two samples (at 1.1 s).
  const double t_turn_s = 1.1;
  const Trajectory log = SampleTurning(4.0, 3.0, t_turn_s);
  double largest_yaw_error = 0.0, largest_yaw_sigma = 0.0;
  for (double t = 0.05; t < 2.95; t += 0.05) {
    const int64_t stamp = kBaseNs + std::llround(t * 1e9);
    const auto interpolated = InterpolateOdometry(
        log, stamp, std::numeric_limits<double>::max(), nullptr);
    ASSERT_TRUE(interpolated.has_value());
    const Rigid3d truth =
        TurningPose(static_cast<double>(stamp - kBaseNs) / 1e9, t_turn_s);
    const double yaw_error =
        std::abs(WrapAngle(YawOf(*interpolated) - YawOf(truth)));
    const double position_error =
        (interpolated->translation - truth.translation).norm();
    const Eigen::Matrix3d covariance =
        OdometryInterpolationCovariance(log, stamp);
    // The stated standard deviation covers the error within 3 sigma (plus
    // double rounding) ...
    EXPECT_LE(yaw_error, 3.0 * std::sqrt(covariance(0, 0)) + 1e-12) << t;
    EXPECT_LE(position_error, 3.0 * std::sqrt(covariance(1, 1)) + 1e-9) << t;
    largest_yaw_error = std::max(largest_yaw_error, yaw_error);
    largest_yaw_sigma =
        std::max(largest_yaw_sigma, std::sqrt(covariance(0, 0)));
  }
  // ... of an error that is real: over a degree at 4 Hz, and the bound is
  // no more than twice the worst case.
  EXPECT_GT(largest_yaw_error * 180.0 / kPi, 1.0);
  EXPECT_LT(std::sqrt(3.0) * largest_yaw_sigma, 2.0 * largest_yaw_error);
}

// The relative covariance is J_i C_i J_i^T + J_j C_j J_j^T with the
// Jacobians of odom_i_from_odom_j; checked against finite differences.
TEST(RelativeMotionInterpolationCovariance, MatchesFiniteDifferences) {
  const Rigid3d pose_i(YawRotation(0.7), Eigen::Vector3d(1.0, 2.0, 0.0));
  const Rigid3d pose_j(YawRotation(1.1), Eigen::Vector3d(1.6, 2.9, 0.0));
  auto relative = [](const Rigid3d& i, const Rigid3d& j) {
    const Rigid3d motion = Inverse(i) * j;
    return Eigen::Vector3d(
        YawOf(motion), motion.translation.x(), motion.translation.y());
  };
  auto perturbed = [](const Rigid3d& pose, int axis, double h) {
    Rigid3d out = pose;
    if (axis == 0) {
      out.rotation = YawRotation(h) * pose.rotation;
    } else {
      out.translation[axis - 1] += h;
    }
    return out;
  };
  const double h = 1e-7;
  Eigen::Matrix3d jacobian_i, jacobian_j;
  for (int axis = 0; axis < 3; ++axis) {
    jacobian_i.col(axis) = (relative(perturbed(pose_i, axis, h), pose_j) -
                            relative(pose_i, pose_j)) /
                           h;
    jacobian_j.col(axis) = (relative(pose_i, perturbed(pose_j, axis, h)) -
                            relative(pose_i, pose_j)) /
                           h;
  }
  Eigen::Matrix3d covariance_i, covariance_j;
  covariance_i << 4e-4, 1e-5, 0.0, 1e-5, 9e-4, 2e-5, 0.0, 2e-5, 1e-4;
  covariance_j = Eigen::Vector3d(1e-4, 2e-4, 3e-4).asDiagonal();
  const Eigen::Matrix3d expected =
      jacobian_i * covariance_i * jacobian_i.transpose() +
      jacobian_j * covariance_j * jacobian_j.transpose();
  const MotionCovariance actual = RelativeMotionInterpolationCovariance(
      pose_i, covariance_i, pose_j, covariance_j);
  const int index[3] = {2, 3, 4};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(actual(index[r], index[c]), expected(r, c), 1e-9)
          << r << " " << c;
    }
  }
  // Nothing about roll, pitch or z.
  for (const int k : {0, 1, 5}) {
    EXPECT_EQ(actual.row(k).norm(), 0.0);
    EXPECT_EQ(actual.col(k).norm(), 0.0);
  }
}

// Pairs of a low-rate log carry the covariance; the solver adds it to the
// noise model's.
TEST(RelativeMotionInterpolationCovariance, ReachesThePairs) {
  const Trajectory log = SampleTurning(4.0, 3.0, 1.1);
  Trajectory camera;
  for (double t = 0.1; t < 2.9; t += 1.0 / 7.0) {
    camera.poses.push_back({kBaseNs + std::llround(t * 1e9), Rigid3d()});
  }
  AssociationOptions options;
  options.keyframe_min_rotation_deg = 0.0;  // every frame
  options.keyframe_min_translation_m = 0.0;
  const AssociationResult result =
      AssociateCameraWithOdometry({camera}, log, options);
  ASSERT_GT(result.pairs.size(), 10u);
  double largest_yaw_sigma = 0.0;
  for (const MotionPair& pair : result.pairs) {
    if (!pair.odom_interpolation_covariance) continue;  // steady motion
    largest_yaw_sigma =
        std::max(largest_yaw_sigma,
                 std::sqrt((*pair.odom_interpolation_covariance)(2, 2)));
  }
  EXPECT_GT(largest_yaw_sigma * 180.0 / kPi, 0.3);
}

}  // namespace
}  // namespace odomcal
