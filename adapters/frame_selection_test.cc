#include "odomcal/adapters/frame_selection.h"

#include <gtest/gtest.h>

namespace odomcal {
namespace {

// Odometry at 10 Hz for 10 s: drives along x at 0.5 m/s for 4 s, stands
// still for 3 s, then turns in place at 0.5 rad/s.
Trajectory MakeOdometry() {
  Trajectory odometry;
  odometry.planar = true;
  double x = 0.0, yaw = 0.0;
  for (int k = 0; k <= 100; ++k) {
    odometry.poses.push_back(
        {k * 100000000LL, Rigid3d(YawRotation(yaw), Eigen::Vector3d(x, 0, 0))});
    const double t = 0.1 * k;
    if (t < 4.0) x += 0.05;
    if (t >= 7.0) yaw += 0.05;
  }
  return odometry;
}

TEST(SelectFrames, DropsStandingStillAndOutsideTheOdometry) {
  std::vector<TimedImage> images;
  for (int k = 0; k <= 120; k += 2) {  // 5 Hz, the last 2 s after the log
    images.push_back({"img" + std::to_string(1000 + k), k * 100000000LL});
  }
  FrameSelectionOptions options;
  options.min_translation_m = 0.15;
  options.min_rotation_deg = 10.0;
  const FrameSelection selection =
      SelectFrames(images, MakeOdometry(), options);
  EXPECT_EQ(selection.num_images, 61);
  EXPECT_EQ(selection.num_outside_odometry, 10);
  // Driving 2 m: one image per 0.2 m (the 0.1 m step of 5 Hz frames is too
  // short); turning 1.5 rad: one per 0.2 rad; none while standing.
  int kept_while_still = 0;
  for (const TimedImage& image : selection.kept) {
    kept_while_still +=
        image.stamp_ns > 4200000000LL && image.stamp_ns < 7000000000LL;
  }
  EXPECT_EQ(kept_while_still, 0);
  EXPECT_EQ(selection.num_images,
            static_cast<int>(selection.kept.size()) +
                selection.num_outside_odometry +
                selection.num_dropped_still_or_close);
  for (size_t i = 1; i < selection.kept.size(); ++i) {
    EXPECT_LT(selection.kept[i - 1].stamp_ns, selection.kept[i].stamp_ns);
  }
  EXPECT_GE(selection.kept.size(), 15u);
  EXPECT_LE(selection.kept.size(), 22u);
}

TEST(SelectFrames, RejectsBadThresholds) {
  FrameSelectionOptions options;
  options.min_translation_m = -1.0;
  EXPECT_THROW(SelectFrames({}, MakeOdometry(), options),
               std::invalid_argument);
  options = FrameSelectionOptions();
  options.max_odometry_gap_s = -1.0;  // 0 is automatic
  try {
    options.Check();
    ADD_FAILURE() << "accepted a zero gap";
  } catch (const std::invalid_argument& error) {
    EXPECT_EQ(std::string(error.what()),
              "max_odometry_gap_s must be finite and > 0, got -1");
  }
}

}  // namespace
}  // namespace odomcal
