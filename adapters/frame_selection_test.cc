#include "odomcal/adapters/frame_selection.h"

#include <gtest/gtest.h>

#include <cmath>

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

TEST(AutomaticFrameSpacing, FollowsTheFieldOfView) {
  // The rendered scenes' camera horizontally: fx 260 px, cx 160 px: 63.2
  // deg (vertically, cy 120 px: 49.6 deg, the narrower field of view that
  // odomcal run gives the selection).
  EXPECT_NEAR(FieldOfViewDeg(260.0, 120.0), 49.6, 0.05);
  const double fov_deg = FieldOfViewDeg(260.0, 160.0);
  EXPECT_NEAR(fov_deg, 2.0 * std::atan(160.0 / 260.0) * 180.0 / M_PI, 1e-12);
  EXPECT_NEAR(fov_deg, 63.2, 0.05);
  const FrameSpacing spacing = AutomaticFrameSpacing(fov_deg);
  EXPECT_NEAR(spacing.min_rotation_deg, fov_deg / 8.0, 1e-12);
  // 2.5 m * tan(3.95 deg): four steps span the mapper's 16 deg at 2.5 m.
  EXPECT_NEAR(spacing.min_translation_m,
              2.5 * std::tan(fov_deg / 16.0 * M_PI / 180.0),
              1e-12);
  EXPECT_NEAR(spacing.min_translation_m, 0.1726, 0.0005);
  // COLMAP's default focal length 1.2 * width: 45.24 deg.
  EXPECT_NEAR(
      FieldOfViewDeg(1.2 * 640.0, 320.0), kColmapDefaultFieldOfViewDeg, 0.01);
  // Given thresholds win over the automatic ones, one at a time.
  FrameSelectionOptions options;
  options.field_of_view_deg = 90.0;
  options.min_translation_m = kAutomaticFrameSpacing;
  options.min_rotation_deg = 2.0;
  const FrameSpacing resolved = ResolvedFrameSpacing(options);
  EXPECT_EQ(resolved.min_rotation_deg, 2.0);
  EXPECT_NEAR(resolved.min_translation_m,
              2.5 * std::tan(90.0 / 16.0 * M_PI / 180.0),
              1e-12);
}

TEST(SelectFrames, AutomaticSpacingKeepsImagesForTriangulation) {
  // 5 Hz images of MakeOdometry's drive (0.1 m and 0.1 rad apart), camera
  // of 63.2 deg: keep an image per 0.1726 m (every second while driving,
  // 0.2 m) or per 7.9 deg (every second while turning, 0.2 rad = 11.5 deg).
  std::vector<TimedImage> images;
  for (int k = 0; k <= 100; k += 2) {
    images.push_back({"img" + std::to_string(1000 + k), k * 100000000LL});
  }
  FrameSelectionOptions options;
  options.min_translation_m = kAutomaticFrameSpacing;
  options.min_rotation_deg = kAutomaticFrameSpacing;
  options.field_of_view_deg = FieldOfViewDeg(260.0, 160.0);
  const FrameSelection selection =
      SelectFrames(images, MakeOdometry(), options);
  EXPECT_NEAR(selection.spacing.min_translation_m, 0.1726, 0.0005);
  std::vector<int64_t> stamps_ms;
  for (const TimedImage& image : selection.kept) {
    stamps_ms.push_back(image.stamp_ns / 1000000);
  }
  // Driving 0-4 s: 0, 0.4, ... 4.0 s (the image at 4.2 s has not moved
  // since 4.0 s); still until 7 s; turning from 7 s: 7.4, 7.8, ... 10 s.
  const std::vector<int64_t> expected = {0,
                                         400,
                                         800,
                                         1200,
                                         1600,
                                         2000,
                                         2400,
                                         2800,
                                         3200,
                                         3600,
                                         4000,
                                         7400,
                                         7800,
                                         8200,
                                         8600,
                                         9000,
                                         9400,
                                         9800};
  EXPECT_EQ(stamps_ms, expected);
}

TEST(SelectFrames, RejectsBadThresholds) {
  FrameSelectionOptions options;
  options.min_translation_m = -0.25;  // -1 is kAutomaticFrameSpacing
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
