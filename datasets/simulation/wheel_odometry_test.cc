#include "odomcal/datasets/simulation/wheel_odometry.h"

#include "odomcal/solver/angles.h"

#include <gtest/gtest.h>

#include <cmath>

namespace odomcal {
namespace {

constexpr int64_t kPeriodNs = 20000000;  // 50 Hz
constexpr double kExact = 1e-9;

std::vector<int64_t> Times(int64_t duration_ns) {
  std::vector<int64_t> times;
  for (int64_t t = 0; t <= duration_ns; t += kPeriodNs) times.push_back(t);
  return times;
}

// 20 s straight at 0.5 m/s, 10 s arc, 10 s standing.
UnicyclePath TestPath() {
  std::vector<PathManoeuvre> m(3);
  m[0] = {0, 20000000000, 0.5, 0.0, PlanarPose{1.0, 2.0, 0.3}};
  m[1] = {20000000000, 10000000000, 0.4, 0.3, PlanarPose()};
  m[2] = {30000000000, 10000000000, 0.0, 0.0, PlanarPose()};
  // Chain the start poses exactly as the planner would.
  UnicyclePath first({m[0]});
  m[1].start = first.PoseAt(m[0].duration_ns);
  UnicyclePath second({m[0], m[1]});
  m[2].start = second.PoseAt(m[1].start_ns + m[1].duration_ns);
  return UnicyclePath(m);
}

double Yaw(const Rigid3d& pose) { return RollPitchYaw(pose.rotation).z(); }

TEST(SimulateWheelOdometry, NoiseFreeEqualsTheTruth) {
  const UnicyclePath path = TestPath();
  const std::vector<int64_t> times = Times(path.duration_ns());
  const Trajectory measured =
      SimulateWheelOdometry(path, times, 100, WheelOdometryNoise());
  const Trajectory truth = TrueWheelOdometry(path, times, 100);
  ASSERT_EQ(measured.poses.size(), truth.poses.size());
  EXPECT_EQ(measured.poses[0].stamp_ns, 100);
  for (size_t i = 0; i < truth.poses.size(); ++i) {
    EXPECT_NEAR((measured.poses[i].world_from_sensor.translation -
                 truth.poses[i].world_from_sensor.translation)
                    .norm(),
                0.0,
                1e-8);
    EXPECT_NEAR(std::remainder(Yaw(measured.poses[i].world_from_sensor) -
                                   Yaw(truth.poses[i].world_from_sensor),
                               2 * kPi),
                0.0,
                kExact);
  }
}

TEST(SimulateWheelOdometry, WheelScaleErrorsAndYawDrift) {
  WheelOdometryNoise noise;
  noise.wheel_scale_error_left = 0.01;
  noise.wheel_scale_error_right = 0.03;
  noise.yaw_rate_bias_radps = 0.002;
  const UnicyclePath path = TestPath();
  const Trajectory odometry =
      SimulateWheelOdometry(path, Times(path.duration_ns()), 0, noise);
  // Straight part (first 20 s): both wheels travel s, so the distance is
  // scaled by 1 + (e_l + e_r) / 2, the heading turns by (e_r - e_l) s / b
  // plus the drift.
  const size_t k = 1000;  // t = 20 s
  const Rigid3d& pose = odometry.poses[k].world_from_sensor;
  const double s = 10.0;
  const double dyaw = (0.03 - 0.01) * s / noise.wheel_base_m + 0.002 * 20.0;
  EXPECT_NEAR(Yaw(pose), dyaw, kExact);
  // A constant-curvature arc of length s(1 + 0.02) turning by dyaw.
  const double chord = s * 1.02 * std::sin(dyaw / 2) / (dyaw / 2);
  EXPECT_NEAR(pose.translation.norm(), chord, 1e-9);
  // Standing (last 10 s): only the drift moves the heading.
  const double yaw_30 = Yaw(odometry.poses[1500].world_from_sensor);
  const double yaw_40 = Yaw(odometry.poses[2000].world_from_sensor);
  EXPECT_NEAR(std::remainder(yaw_40 - yaw_30, 2 * kPi), 0.002 * 10.0, kExact);
  EXPECT_EQ(odometry.poses[1500].world_from_sensor.translation,
            odometry.poses[2000].world_from_sensor.translation);
}

// Per-period distance ratio measured / true = (l' + r') / (2 s) on a
// straight line: mean 1, standard deviation slip / sqrt(2).
TEST(SimulateWheelOdometry, SlipStatistics) {
  WheelOdometryNoise noise;
  noise.wheel_slip_stddev = 0.02;
  noise.seed = 4;
  std::vector<PathManoeuvre> m = {{0, 400000000000, 0.5, 0.0, PlanarPose()}};
  const UnicyclePath path(m);
  const Trajectory odometry =
      SimulateWheelOdometry(path, Times(path.duration_ns()), 0, noise);
  const double step = 0.5 * 1e-9 * kPeriodNs;
  double sum = 0.0, sum_sq = 0.0;
  const size_t n = odometry.poses.size() - 1;
  for (size_t i = 0; i < n; ++i) {
    // The chord is at most 1e-7 shorter than the arc for these turns.
    const double ratio = (odometry.poses[i + 1].world_from_sensor.translation -
                          odometry.poses[i].world_from_sensor.translation)
                             .norm() /
                         step;
    sum += ratio;
    sum_sq += ratio * ratio;
  }
  const double mean = sum / n;
  const double stddev = std::sqrt(sum_sq / n - mean * mean);
  // n = 20000: standard errors 1e-4 (mean) and 0.5 % (stddev).
  EXPECT_NEAR(mean, 1.0, 5e-4);
  EXPECT_NEAR(stddev, 0.02 / std::sqrt(2.0), 0.02 / std::sqrt(2.0) * 0.03);
  EXPECT_THROW(SimulateWheelOdometry(path, {5, 5}, 0, noise),
               std::invalid_argument);
}

}  // namespace
}  // namespace odomcal
