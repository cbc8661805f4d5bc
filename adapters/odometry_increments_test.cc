#include "odomcal/adapters/odometry_increments.h"

#include "odomcal/adapters/association.h"
#include "odomcal/solver/odometry_intrinsics.h"
#include "odomcal/solver/rigid3.h"

#include <gtest/gtest.h>

#include <cmath>

namespace odomcal {
namespace {

// A unicycle arc (0.5 m/s, 0.4 rad/s) sampled at 4 Hz.
Trajectory Arc() {
  Trajectory odometry;
  odometry.planar = true;
  for (int k = 0; k < 5; ++k) {
    const double t = 0.25 * k, yaw = 0.4 * t, radius = 0.5 / 0.4;
    odometry.poses.push_back(
        {1000000000 + 250000000LL * k,
         Rigid3d(YawRotation(yaw),
                 Eigen::Vector3d(radius * std::sin(yaw),
                                 radius * (1.0 - std::cos(yaw)),
                                 0.0))});
  }
  return odometry;
}

// With identity intrinsics the samples give back the association's motion,
// also for a stamp the association continues beyond the last sample.
TEST(AttachOdometrySamples, ReproducesTheInterpolatedMotionAlsoBeyondTheEnd) {
  const Trajectory odometry = Arc();
  const int64_t last = odometry.poses.back().stamp_ns;
  for (const int64_t stamp_j : {last - 100000000, last, last + 20000000}) {
    MotionPair pair;
    pair.stamp_i_ns = odometry.poses[1].stamp_ns + 100000000;
    pair.stamp_j_ns = stamp_j;
    const auto at_i =
        InterpolateOdometry(odometry, pair.stamp_i_ns, 1.0, nullptr);
    const auto at_j =
        InterpolateOdometry(odometry, pair.stamp_j_ns, 1.0, nullptr);
    ASSERT_TRUE(at_i && at_j) << stamp_j;
    const Rigid3d expected = Inverse(*at_i) * *at_j;
    MotionPairs pairs = {pair};
    AttachOdometrySamples(odometry, &pairs);
    ASSERT_TRUE(pairs[0].odometry_samples.has_value());
    const double identity[3] = {1.0, 0.0, 0.0};
    const PlanarMotion<double> motion =
        CorrectedOdometryMotion(*pairs[0].odometry_samples, identity, 0.0, 0.0);
    EXPECT_NEAR(motion.x, expected.translation.x(), 1e-12) << stamp_j;
    EXPECT_NEAR(motion.y, expected.translation.y(), 1e-12) << stamp_j;
    const Eigen::Vector3d heading =
        expected.rotation * Eigen::Vector3d::UnitX();
    EXPECT_NEAR(motion.yaw, std::atan2(heading.y(), heading.x()), 1e-12)
        << stamp_j;
  }
}

}  // namespace
}  // namespace odomcal
