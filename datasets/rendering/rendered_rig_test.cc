#include "odomcal/datasets/rendering/rendered_rig.h"

#include "odomcal/adapters/image_timestamps.h"
#include "odomcal/adapters/timestamp.h"
#include "odomcal/datasets/rendering/dataset_presets.h"
#include "odomcal/datasets/simulation/camera_mount.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

namespace odomcal {
namespace {

// Poses composed from the same doubles: equal to rounding.
constexpr double kRigPoseExact = 1e-12;

// The small preset at 80x60 with coarse textures: milliseconds per image.
RenderedDatasetOptions TinyRigOptions(uint64_t seed, int num_images) {
  RenderedDatasetOptions options = MakeDatasetPreset("small", seed);
  options.camera = {80, 60, 65.0, 65.0, 40.0, 30.0, 0.0};
  options.num_images = num_images;
  options.scene.texel_size_m = 0.03;
  return options;
}

double RigPoseDistance(const Rigid3d& a, const Rigid3d& b) {
  return RotationAngle(a.rotation.conjugate() * b.rotation) +
         (a.translation - b.translation).norm();
}

// Runs `check` and expects std::invalid_argument mentioning `field`.
template <typename F>
void ExpectRefusalNaming(F check, const std::string& field) {
  try {
    check();
    ADD_FAILURE() << "accepted; expected a refusal naming " << field;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
  }
}

TEST(RigLayout, CheckNamesTheBadField) {
  const RigLayout good = MakeRigLayout("surround3");
  good.Check();
  RigLayout rig = good;
  rig.cameras.clear();
  ExpectRefusalNaming([&] { rig.Check(); }, "RigLayout.cameras");
  for (const char* name : {"", "a/b", ".hidden", "..", "x y"}) {
    rig = good;
    rig.cameras[1].name = name;
    ExpectRefusalNaming([&] { rig.Check(); }, "RigCamera.name");
  }
  rig = good;
  rig.cameras[2].name = rig.cameras[0].name;
  ExpectRefusalNaming([&] { rig.Check(); }, "named twice");
  rig = good;
  rig.cameras[1].rate_hz = 0.0;
  ExpectRefusalNaming([&] { rig.Check(); }, "rate_hz");
  rig = good;
  rig.cameras[1].phase_s = -0.1;
  ExpectRefusalNaming([&] { rig.Check(); }, "phase_s");
  rig = good;
  rig.cameras[0].phase_s = 0.1;
  ExpectRefusalNaming([&] { rig.Check(); }, "reference camera");
  rig = good;
  rig.cameras[1].time_offset_s = NAN;
  ExpectRefusalNaming([&] { rig.Check(); }, "time_offset_s");
  rig = good;
  rig.cameras[1].odom_from_cam.rotation.coeffs() *= 2.0;
  ExpectRefusalNaming([&] { rig.Check(); }, "odom_from_cam");
  rig = good;
  rig.cameras[1].intrinsics = CameraIntrinsics{0, 60, 65, 65, 40, 30, 0};
  ExpectRefusalNaming([&] { rig.Check(); }, "width");
  ExpectRefusalNaming([&] { rig.Camera("left"); }, "front_left, rear, right");
  ExpectRefusalNaming([] { MakeRigLayout("nope"); }, "stereo, surround3");
}

TEST(RigLayout, BuiltInRigs) {
  const RigLayout stereo = MakeRigLayout("stereo");
  ASSERT_EQ(stereo.cameras.size(), 2u);
  const Rigid3d right_from_left = Inverse(stereo.cameras[1].odom_from_cam) *
                                  stereo.cameras[0].odom_from_cam;
  EXPECT_NEAR(right_from_left.translation.norm(), 0.12, 1e-12);
  EXPECT_LT(RotationAngle(right_from_left.rotation), 1e-12);
  for (const RigCamera& camera : stereo.cameras) {
    EXPECT_FALSE(camera.rate_hz.has_value());  // the preset's, both
    EXPECT_EQ(camera.phase_s, 0.0);
  }
  const RigLayout surround = MakeRigLayout("surround3");
  ASSERT_EQ(surround.cameras.size(), 3u);
  const double yaws_deg[] = {30.0, 180.0, -90.0};
  const double rates_hz[] = {5.0, 4.0, 5.0};
  for (size_t c = 0; c < 3; ++c) {
    const RigCamera& camera = surround.cameras[c];
    const Eigen::Vector3d axis =
        camera.odom_from_cam.rotation * Eigen::Vector3d::UnitZ();
    EXPECT_NEAR(std::atan2(axis.y(), axis.x()) * 180.0 / M_PI,
                yaws_deg[c] == 180.0 && axis.y() < 0 ? -180.0 : yaws_deg[c],
                1e-9)
        << camera.name;
    EXPECT_EQ(*camera.rate_hz, rates_hz[c]);
    EXPECT_LE(camera.odom_from_cam.translation.head<2>().norm(), 0.26);
  }
  const RigLayout four = MakeRigLayout("surround4");
  ASSERT_EQ(four.cameras.size(), 4u);
  const double four_yaws_deg[] = {0.0, 90.0, 180.0, -90.0};
  std::set<double> phases;
  for (size_t c = 0; c < 4; ++c) {
    const RigCamera& camera = four.cameras[c];
    const Eigen::Vector3d axis =
        camera.odom_from_cam.rotation * Eigen::Vector3d::UnitZ();
    const double yaw_deg = std::atan2(axis.y(), axis.x()) * 180.0 / M_PI;
    EXPECT_NEAR(
        std::abs(yaw_deg) > 179.0 ? 180.0 : yaw_deg, four_yaws_deg[c], 1e-9)
        << camera.name;
    EXPECT_FALSE(camera.rate_hz.has_value());  // the preset's
    phases.insert(camera.phase_s);
  }
  EXPECT_EQ(phases.size(), 4u);  // no two capture together
  EXPECT_NO_THROW(four.Check());
}

TEST(RenderedRig, CamerasCaptureAtTheirRatesAndPhasesWithinTheDrive) {
  const RenderedDatasetOptions options = TinyRigOptions(1, 20);
  const RigLayout layout = MakeRigLayout("surround3");
  EXPECT_EQ(RigReferenceImageCount(MakeDatasetPreset("small", 1), layout),
            79);  // 15.6 s at 5 Hz
  const RenderedRig rig = SimulateRigMotion(options, layout);
  ASSERT_EQ(rig.cameras.size(), 3u);
  const int64_t start_ns =
      options.start_stamp_ns + SecondsToNs(options.lead_time_s);
  const int64_t last_ns = rig.cameras[0].frames.back().capture_ns;
  EXPECT_EQ(last_ns - start_ns, SecondsToNs(19 / 5.0));
  const std::regex name_rule("[A-Za-z_]+/[0-9]{19}\\.png");
  // 3.8 s of images: 0 + k / 5, 0.07 + k / 4, 0.1 + k / 5 s.
  const size_t expected_counts[] = {20, 15, 19};
  for (size_t c = 0; c < rig.cameras.size(); ++c) {
    const RenderedRigCamera& camera = rig.cameras[c];
    SCOPED_TRACE(camera.camera.name);
    const int64_t period_ns = SecondsToNs(1.0 / *camera.camera.rate_hz);
    const std::vector<RenderedFrame>& frames = camera.frames;
    EXPECT_EQ(frames.size(), expected_counts[c]);
    EXPECT_EQ(frames.front().capture_ns,
              start_ns + SecondsToNs(camera.camera.phase_s));
    for (size_t k = 1; k < frames.size(); ++k) {
      EXPECT_NEAR(
          frames[k].capture_ns - frames[k - 1].capture_ns, period_ns, 1);
    }
    EXPECT_LE(frames.back().capture_ns, last_ns);
    EXPECT_GT(frames.back().capture_ns + period_ns, last_ns);
    for (const RenderedFrame& frame : frames) {
      EXPECT_EQ(frame.stamp_ns, frame.capture_ns);  // no offset, no jitter
      EXPECT_TRUE(std::regex_match(frame.image_name, name_rule))
          << frame.image_name;
      // The name is the stamp, as the file-name rule of image_timestamps.h
      // reads it.
      EXPECT_EQ(TimestampFromImageName(frame.image_name, std::nullopt, nullptr),
                frame.stamp_ns);
    }
  }
  // The drive's odometry covers every camera with the lead time to spare.
  EXPECT_GE(rig.drive.odometry.poses.back().stamp_ns,
            last_ns + SecondsToNs(options.lead_time_s));
}

// The reference camera's frames and the drive are the single-camera
// dataset's for the reference's mount and rate, jitter and offset included.
TEST(RenderedRig, ReferenceIsTheSingleCameraDataset) {
  RenderedDatasetOptions options = TinyRigOptions(3, 12);
  options.camera_time_offset_s = 0.025;
  options.camera_time_jitter_s = 0.002;
  RigLayout layout = MakeRigLayout("surround3");
  layout.cameras[0].time_offset_s = 0.005;
  const RenderedRig rig = SimulateRigMotion(options, layout);
  RenderedDatasetOptions single = options;
  single.odom_from_cam = layout.cameras[0].odom_from_cam;
  single.camera_rate_hz = 5.0;
  single.camera_time_offset_s = 0.030;
  const RenderedDataset expected = SimulateDatasetMotion(single);
  ASSERT_EQ(rig.cameras[0].frames.size(), expected.frames.size());
  for (size_t k = 0; k < expected.frames.size(); ++k) {
    const RenderedFrame& frame = rig.cameras[0].frames[k];
    EXPECT_EQ(frame.capture_ns, expected.frames[k].capture_ns);
    EXPECT_EQ(frame.stamp_ns, expected.frames[k].stamp_ns);
    EXPECT_NE(frame.stamp_ns, frame.capture_ns + SecondsToNs(0.030));
    EXPECT_EQ(RigPoseDistance(frame.origin_from_cam,
                              expected.frames[k].origin_from_cam),
              0.0);
    EXPECT_EQ(rig.drive.frames[k].image_name, frame.image_name);
  }
  ASSERT_EQ(rig.drive.odometry.poses.size(), expected.odometry.poses.size());
  EXPECT_EQ(RigPoseDistance(rig.drive.odometry.poses.back().world_from_sensor,
                            expected.odometry.poses.back().world_from_sensor),
            0.0);
  // Other cameras: the preset's offset only, and jitter of their own.
  for (const RenderedFrame& frame : rig.cameras[1].frames) {
    EXPECT_NEAR(1e-9 * (frame.stamp_ns - frame.capture_ns), 0.025, 0.01);
  }
  EXPECT_DOUBLE_EQ(rig.cameras[0].camera_time_offset_s, 0.030);
  EXPECT_DOUBLE_EQ(rig.cameras[1].camera_time_offset_s, 0.025);
}

// On a road the car rides on the ground: the rig's poses (RoomFromOdomAt)
// are the single-camera dataset's, pitch and bank included.
TEST(RenderedRig, RoadRigRidesOnTheGround) {
  RenderedDatasetOptions options = MakeDatasetPreset("road_sloped", 2);
  options.num_images = 6;
  const RigLayout layout = MakeRigLayout("stereo");
  const RenderedRig rig = SimulateRigMotion(options, layout);
  RenderedDatasetOptions single = options;
  single.odom_from_cam = layout.cameras[0].odom_from_cam;
  const RenderedDataset expected = SimulateDatasetMotion(single);
  ASSERT_EQ(rig.cameras[0].frames.size(), expected.frames.size());
  double largest_tilt = 0.0;
  for (size_t k = 0; k < expected.frames.size(); ++k) {
    EXPECT_EQ(RigPoseDistance(rig.cameras[0].frames[k].origin_from_cam,
                              expected.frames[k].origin_from_cam),
              0.0);
    const Rigid3d room_from_odom = RoomFromOdomAt(
        rig.drive, expected.frames[k].capture_ns - options.start_stamp_ns);
    const Eigen::Vector3d up =
        room_from_odom.rotation * Eigen::Vector3d::UnitZ();
    largest_tilt = std::max(largest_tilt, std::acos(std::min(1.0, up.z())));
  }
  EXPECT_GT(largest_tilt, 0.001);  // the ground is sloped here
}

TEST(RenderedRig, EveryCameraIsTheRobotPoseTimesItsMount) {
  const RenderedRig rig =
      SimulateRigMotion(TinyRigOptions(2, 15), MakeRigLayout("surround3"));
  const RenderedDatasetOptions& o = rig.drive.options;
  const Rigid3d origin_from_room =
      Inverse(rig.drive.path.PoseAt(0).ToRigid3d());
  for (const RenderedRigCamera& camera : rig.cameras) {
    for (const RenderedFrame& frame : camera.frames) {
      const Rigid3d expected =
          origin_from_room *
          rig.drive.path.PoseAt(frame.capture_ns - o.start_stamp_ns)
              .ToRigid3d() *
          camera.camera.odom_from_cam;
      EXPECT_LT(RigPoseDistance(frame.origin_from_cam, expected),
                kRigPoseExact);
    }
  }
}

TEST(RenderedRig, SynchronisedCamerasShareImageNamesOthersDoNot) {
  const RenderedDatasetOptions options = TinyRigOptions(1, 8);
  const RenderedRig stereo =
      SimulateRigMotion(options, MakeRigLayout("stereo"));
  ASSERT_EQ(stereo.cameras[1].frames.size(), 8u);
  for (size_t k = 0; k < 8; ++k) {
    EXPECT_EQ(stereo.cameras[0].frames[k].capture_ns,
              stereo.cameras[1].frames[k].capture_ns);
    EXPECT_EQ(stereo.cameras[0].frames[k].image_name.substr(5),   // "left/"
              stereo.cameras[1].frames[k].image_name.substr(6));  // "right/"
  }
  const RenderedRig surround =
      SimulateRigMotion(options, MakeRigLayout("surround3"));
  std::set<int64_t> captures;
  size_t count = 0;
  for (const RenderedRigCamera& camera : surround.cameras) {
    for (const RenderedFrame& frame : camera.frames) {
      captures.insert(frame.capture_ns);
      ++count;
    }
  }
  EXPECT_EQ(captures.size(), count);
}

TEST(RenderedRig, CappedCameraImageIsUniformTheOthersAreNot) {
  RigLayout layout = MakeRigLayout("stereo");
  layout.cameras[1].capped = true;
  layout.cameras[1].intrinsics = CameraIntrinsics{40, 30, 32, 32, 20, 15, 0};
  const RenderedRig rig = SimulateRenderedRig(TinyRigOptions(4, 2), layout);
  const Image open = RenderRigFrame(rig, 0, 1);
  const Image capped = RenderRigFrame(rig, 1, 1);
  EXPECT_EQ(open.width, 80);
  ASSERT_EQ(capped.width, 40);
  ASSERT_EQ(capped.height, 30);
  ASSERT_EQ(capped.rgb.size(), 40u * 30u * 3u);
  for (const uint8_t value : capped.rgb) {
    ASSERT_EQ(value, kCappedImageValue);
  }
  const auto [lowest, highest] =
      std::minmax_element(open.rgb.begin(), open.rgb.end());
  EXPECT_GT(*highest - *lowest, 100);
  EXPECT_THROW(RenderRigFrame(rig, 1, 2), std::invalid_argument);
  EXPECT_THROW(RenderRigFrame(rig, 2, 0), std::invalid_argument);
}

TEST(RenderedRig, RefusesACameraWithoutTwoFramesOrFasterThanTheOdometry) {
  RigLayout layout = MakeRigLayout("surround3");
  layout.cameras[1].phase_s = 3.0;  // the drive's images span 1.4 s
  ExpectRefusalNaming(
      [&] { SimulateRigMotion(TinyRigOptions(1, 8), layout); },
      "rig camera 'rear': fewer than 2 frames in the drive's 1.400 s");
  layout = MakeRigLayout("surround3");
  layout.cameras[2].rate_hz = 60.0;
  ExpectRefusalNaming([&] { SimulateRigMotion(TinyRigOptions(1, 8), layout); },
                      "rig camera 'right': rate_hz above odometry_rate_hz");
}

TEST(RenderedRig, GroundTruthListsEveryCameraWithItsMount) {
  RigLayout layout = MakeRigLayout("surround3");
  layout.cameras[1].capped = true;
  layout.cameras[2].intrinsics = CameraIntrinsics{40, 30, 32, 33, 20, 15, 0};
  layout.cameras[2].time_offset_s = 0.01;
  const RenderedRig rig = SimulateRigMotion(TinyRigOptions(5, 10), layout);
  const nlohmann::json truth = nlohmann::json::parse(RigGroundTruthJson(rig));
  EXPECT_EQ(truth["rig"]["name"], "surround3");
  EXPECT_EQ(truth["rig"]["reference_camera"], "front_left");
  ASSERT_EQ(truth["cameras"].size(), 3u);
  for (size_t c = 0; c < 3; ++c) {
    const nlohmann::json& camera = truth["cameras"][c];
    const RigCamera& given = layout.cameras[c];
    SCOPED_TRACE(given.name);
    EXPECT_EQ(camera["name"], given.name);
    EXPECT_EQ(camera["camera_id"], c + 1);
    EXPECT_EQ(camera["image_prefix"], given.name + "/");
    EXPECT_EQ(camera["reference"], c == 0);
    EXPECT_EQ(camera["capped"], c == 1);
    EXPECT_EQ(camera["rate_hz"], *given.rate_hz);
    EXPECT_EQ(camera["phase_s"], given.phase_s);
    const auto& q = camera["odom_from_cam"]["quaternion_wxyz"];
    const Eigen::Quaterniond mount(q[0], q[1], q[2], q[3]);
    EXPECT_LT(RotationAngle(mount.conjugate() * given.odom_from_cam.rotation),
              kRigPoseExact);
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(camera["odom_from_cam"]["translation_m"][i],
                given.odom_from_cam.translation[i]);
      EXPECT_EQ(camera["odom_from_cam"]["matrix"][i][3],
                given.odom_from_cam.translation[i]);
    }
    EXPECT_EQ(camera["num_images"], rig.cameras[c].frames.size());
    ASSERT_EQ(camera["images"].size(), rig.cameras[c].frames.size());
    EXPECT_EQ(camera["images"][1]["name"], rig.cameras[c].frames[1].image_name);
    EXPECT_EQ(camera["images"][1]["timestamp"],
              FormatTimestampSeconds(rig.cameras[c].frames[1].stamp_ns));
  }
  EXPECT_EQ(truth["cameras"][0]["camera"]["params"],
            nlohmann::json({65.0, 65.0, 40.0, 30.0}));
  EXPECT_EQ(truth["cameras"][2]["camera"]["params"],
            nlohmann::json({32.0, 33.0, 20.0, 15.0}));
  EXPECT_EQ(truth["cameras"][2]["camera"]["width"], 40);
  EXPECT_DOUBLE_EQ(truth["cameras"][2]["camera_time_offset_s"].get<double>(),
                   0.01);
  // The single-camera fields are the reference camera's.
  EXPECT_EQ(truth["odom_from_cam"], truth["cameras"][0]["odom_from_cam"]);
  EXPECT_EQ(truth["camera"], truth["cameras"][0]["camera"]);
  EXPECT_EQ(truth["images"], truth["cameras"][0]["images"]);
  EXPECT_EQ(truth["timing"]["camera_rate_hz"], 5.0);
}

TEST(RenderedRig, WritesOneFolderPerCameraTheTimesAndTheIntrinsics) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "odomcal_rendered_rig_test";
  std::filesystem::remove_all(dir);
  RigLayout layout = MakeRigLayout("surround3");
  layout.cameras[2].capped = true;
  layout.cameras[2].intrinsics =
      CameraIntrinsics{40, 30, 32.5, 32.5, 20, 15, 0};
  const RenderedRig rig = SimulateRenderedRig(TinyRigOptions(6, 4), layout);
  size_t total = 0;
  for (const RenderedRigCamera& camera : rig.cameras) {
    total += camera.frames.size();
  }
  EXPECT_EQ(total, 4u + 3u + 3u);  // 0.6 s of images at 5, 4, 5 Hz
  size_t calls = 0;
  WriteRenderedRig(rig, dir.string(), [&](size_t done, size_t all) {
    EXPECT_EQ(done, ++calls);
    EXPECT_EQ(all, total);
  });
  EXPECT_EQ(calls, total);
  const std::map<std::string, int64_t> stamps = ReadImageTimestampsCsv(
      (dir / "image_timestamps.csv").string(), TimeUnit::kSeconds);
  EXPECT_EQ(stamps.size(), total);
  for (const RenderedRigCamera& camera : rig.cameras) {
    size_t files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(
             dir / "images" / camera.camera.name)) {
      (void)entry;
      ++files;
    }
    EXPECT_EQ(files, camera.frames.size());
    for (const RenderedFrame& frame : camera.frames) {
      EXPECT_EQ(stamps.at(frame.image_name), frame.stamp_ns);
      const cv::Mat image = cv::imread(
          (dir / "images" / frame.image_name).string(), cv::IMREAD_COLOR);
      ASSERT_FALSE(image.empty()) << frame.image_name;
      EXPECT_EQ(image.cols, camera.camera.intrinsics->width);
    }
  }
  std::ifstream cameras_file(dir / "cameras.txt");
  std::vector<std::string> lines;
  for (std::string line; std::getline(cameras_file, line);) {
    if (!line.empty() && line[0] != '#') lines.push_back(line);
  }
  EXPECT_EQ(lines,
            (std::vector<std::string>{"1 PINHOLE 80 60 65 65 40 30",
                                      "2 PINHOLE 80 60 65 65 40 30",
                                      "3 PINHOLE 40 30 32.5 32.5 20 15"}));
  std::ifstream json_file(dir / "ground_truth.json");
  const nlohmann::json truth = nlohmann::json::parse(json_file);
  EXPECT_EQ(truth["cameras"].size(), 3u);
  EXPECT_TRUE(std::filesystem::exists(dir / "odometry.csv"));
  EXPECT_TRUE(std::filesystem::exists(dir / "odometry_ground_truth.csv"));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace odomcal
