#include "odomcal/datasets/rendering/rendered_dataset.h"

#include "odomcal/adapters/trajectory_io.h"
#include "odomcal/datasets/rendering/dataset_presets.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace odomcal {
namespace {

constexpr double kExact = 1e-12;

// The small preset, cut down so that tests render in milliseconds.
RenderedDatasetOptions TinyOptions(uint64_t seed) {
  RenderedDatasetOptions options = MakeDatasetPreset("small", seed);
  options.camera = {80, 60, 65.0, 65.0, 40.0, 30.0, 0.0};
  options.num_images = 6;
  options.scene.texel_size_m = 0.03;  // small textures, fast to build
  return options;
}

double PoseDistance(const Rigid3d& a, const Rigid3d& b) {
  return RotationAngle(a.rotation.conjugate() * b.rotation) +
         (a.translation - b.translation).norm();
}

TEST(RenderedDataset, SameSeedSameBytesOtherSeedOtherImages) {
  const RenderedDataset a = SimulateRenderedDataset(TinyOptions(3));
  const RenderedDataset b = SimulateRenderedDataset(TinyOptions(3));
  const RenderedDataset c = SimulateRenderedDataset(TinyOptions(4));
  for (size_t i : {size_t{0}, size_t{5}}) {
    EXPECT_EQ(RenderFrame(a, i).rgb, RenderFrame(b, i).rgb);
    EXPECT_NE(RenderFrame(a, i).rgb, RenderFrame(c, i).rgb);
  }
}

// Image poses are the true odometry composed with the mount, at the capture
// times; where a capture coincides with an odometry sample they agree with
// the written ground-truth odometry exactly.
TEST(RenderedDataset, GroundTruthPosesAreOdometryTimesMount) {
  RenderedDatasetOptions options = TinyOptions(1);
  options.num_images = 20;
  const RenderedDataset dataset = SimulateDatasetMotion(options);
  const Rigid3d origin_from_room = Inverse(dataset.path.PoseAt(0).ToRigid3d());
  int coinciding = 0;
  for (const RenderedFrame& frame : dataset.frames) {
    const int64_t t = frame.capture_ns - options.start_stamp_ns;
    const Rigid3d expected = origin_from_room *
                             dataset.path.PoseAt(t).ToRigid3d() *
                             options.odom_from_cam;
    EXPECT_LT(PoseDistance(frame.origin_from_cam, expected), kExact);
    for (const StampedPose& sample : dataset.true_odometry.poses) {
      if (sample.stamp_ns != frame.capture_ns) continue;
      ++coinciding;
      EXPECT_LT(PoseDistance(frame.origin_from_cam,
                             sample.world_from_sensor * options.odom_from_cam),
                1e-9);
    }
    EXPECT_EQ(frame.stamp_ns, frame.capture_ns);  // no offset, no jitter
  }
  EXPECT_GE(coinciding, 5);  // 2.5 Hz captures lie on the 50 Hz grid
  // The odometry covers the images with the lead time on both sides.
  EXPECT_LE(dataset.odometry.poses.front().stamp_ns,
            dataset.frames.front().capture_ns - 500000000);
  EXPECT_GE(dataset.odometry.poses.back().stamp_ns,
            dataset.frames.back().capture_ns + 500000000);
  EXPECT_LT(
      PoseDistance(dataset.true_odometry.poses[0].world_from_sensor, Rigid3d()),
      kExact);
}

TEST(RenderedDataset, TimeOffsetAndJitter) {
  RenderedDatasetOptions options = TinyOptions(2);
  options.num_images = 200;
  options.camera_time_offset_s = 0.025;
  options.camera_time_jitter_s = 0.002;
  const RenderedDataset dataset = SimulateDatasetMotion(options);
  double sum = 0.0, sum_sq = 0.0;
  for (const RenderedFrame& frame : dataset.frames) {
    const double d = 1e-9 * (frame.stamp_ns - frame.capture_ns) - 0.025;
    sum += d;
    sum_sq += d * d;
  }
  const double n = dataset.frames.size();
  EXPECT_NEAR(sum / n, 0.0, 0.0006);  // 3 standard errors
  EXPECT_NEAR(std::sqrt(sum_sq / n), 0.002, 0.0004);
}

TEST(RenderedDataset, WritesTheFiles) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "odomcal_rendered_dataset_test";
  std::filesystem::remove_all(dir);
  RenderedDatasetOptions options = TinyOptions(5);
  options.camera_time_offset_s = 0.01;
  const RenderedDataset dataset = SimulateRenderedDataset(options);
  size_t calls = 0;
  WriteRenderedDataset(dataset, dir.string(), [&](size_t done, size_t total) {
    EXPECT_EQ(done, ++calls);
    EXPECT_EQ(total, 6u);
  });
  EXPECT_EQ(calls, 6u);
  const cv::Mat image =
      cv::imread((dir / "images" / "000005.png").string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(image.empty());
  EXPECT_EQ(image.cols, 80);
  EXPECT_EQ(image.rows, 60);
  // Odometry reads back with the adapters' reader.
  const Trajectory odometry =
      ReadOdometryCsv((dir / "odometry.csv").string(), TimeUnit::kSeconds);
  EXPECT_EQ(odometry.poses.size(), dataset.odometry.poses.size());
  EXPECT_EQ(odometry.poses.back().stamp_ns,
            dataset.odometry.poses.back().stamp_ns);
  // Timestamps: a header, then name,seconds with 9 decimals.
  std::ifstream timestamps(dir / "image_timestamps.csv");
  std::string line;
  std::getline(timestamps, line);
  EXPECT_EQ(line, "image_name,timestamp");
  std::getline(timestamps, line);
  EXPECT_EQ(line,
            "000000.png," + FormatTimestampSeconds(dataset.frames[0].stamp_ns));
  EXPECT_EQ(line.size() - line.find('.', 11), 10u);  // ".123456789"
  // Ground truth.
  std::ifstream json_file(dir / "ground_truth.json");
  const nlohmann::json truth = nlohmann::json::parse(json_file);
  EXPECT_EQ(truth["preset"], "small");
  EXPECT_EQ(truth["seed"], 5);
  EXPECT_EQ(truth["camera"]["model"], "PINHOLE");
  EXPECT_EQ(truth["camera"]["params"],
            nlohmann::json({65.0, 65.0, 40.0, 30.0}));
  EXPECT_EQ(truth["images"].size(), 6u);
  const auto& q = truth["odom_from_cam"]["quaternion_wxyz"];
  const Eigen::Quaterniond mount(q[0], q[1], q[2], q[3]);
  EXPECT_LT(RotationAngle(mount.conjugate() * options.odom_from_cam.rotation),
            1e-12);
  EXPECT_EQ(truth["odom_from_cam"]["matrix"][0][3],
            options.odom_from_cam.translation.x());
  EXPECT_EQ(truth["images"][2]["timestamp"],
            FormatTimestampSeconds(dataset.frames[2].stamp_ns));
  const auto& p = truth["images"][2]["world_from_cam"]["translation_m"];
  EXPECT_NEAR(p[0].get<double>(),
              dataset.frames[2].origin_from_cam.translation.x(),
              1e-12);
  EXPECT_DOUBLE_EQ(truth["timing"]["camera_time_offset_s"].get<double>(), 0.01);
  std::filesystem::remove_all(dir);
}

// The preset's first frame is rich: hardly any background, strong contrast.
TEST(RenderedDataset, SmallPresetFrameIsTexturedEverywhere) {
  RenderedDatasetOptions options = MakeDatasetPreset("small", 0);
  options.num_images = 2;
  const RenderedDataset dataset = SimulateRenderedDataset(options);
  const Image image = RenderFrame(dataset, 0);
  ASSERT_EQ(image.width, 320);
  int black = 0;
  double sum = 0.0, sum_sq = 0.0;
  for (size_t i = 0; i < image.rgb.size(); i += 3) {
    const double v = (image.rgb[i] + image.rgb[i + 1] + image.rgb[i + 2]) / 3.0;
    black += v == 0.0;
    sum += v;
    sum_sq += v * v;
  }
  const double n = image.rgb.size() / 3.0;
  EXPECT_LT(black, 0.01 * n);
  EXPECT_GT(std::sqrt(sum_sq / n - (sum / n) * (sum / n)), 25.0);
}

TEST(MakeDatasetPreset, UnknownNameListsTheValidOnes) {
  try {
    MakeDatasetPreset("nope", 0);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(
        std::string(e.what()).find("small, default, tilted, hard, straight"),
        std::string::npos);
  }
}

}  // namespace
}  // namespace odomcal
