// ExtractBag on bags written by Debian's python3-rosbag
// (tests/fixtures/bags/make_extract_bags.py); the written files are read back
// with odomcal's own readers and compared with the values given to rosbag
// (expected.json).
#include "odomcal/adapters/bag/bag_extraction.h"

#include "odomcal/adapters/bag/ros1_bag_reader.h"
#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/image_timestamps.h"
#include "odomcal/adapters/test_support.h"
#include "odomcal/adapters/trajectory_io.h"
#include "odomcal/solver/rigid3.h"
#include "odomcal/tests/scratch_folder_test.h"
#include "odomcal/tests/test_files.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace odomcal::bag {
namespace {

namespace fs = std::filesystem;

std::string BagPath(const std::string& name) {
  return (fs::path(ODOMCAL_EXTRACT_FIXTURE_DIR) / name).string();
}

const nlohmann::json& Expected() {
  static const nlohmann::json expected = nlohmann::json::parse(
      ReadFile(fs::path(ODOMCAL_EXTRACT_FIXTURE_DIR) / "expected.json"));
  return expected;
}

class BagExtractionTest : public ScratchFolderTest {
 protected:
  BagExtractionTest() : ScratchFolderTest("bag_extraction_") {}

  BagExtractionSummary Extract(const std::string& bag,
                               BagExtractionOptions options,
                               const std::string& folder = "out") {
    options.output_folder = Path(folder);
    const auto reader = OpenRos1Bag(BagPath(bag), {});
    return ExtractBag(*reader, options, [this](int64_t done, int64_t total) {
      last_done_ = done;
      last_total_ = total;
    });
  }

  // camera.txt as a COLMAP text model, read by odomcal's COLMAP reader.
  ColmapCamera ReadCamera(const std::string& folder) {
    const fs::path model = dir_ / "model";
    fs::create_directories(model);
    fs::copy_file(dir_ / folder / "camera.txt",
                  model / "cameras.txt",
                  fs::copy_options::overwrite_existing);
    std::ofstream(model / "images.txt") << "";
    std::ofstream(model / "points3D.txt") << "";
    const ColmapModel read = ReadColmapModel(model.string());
    EXPECT_EQ(read.cameras.size(), 1u);
    return read.cameras.begin()->second;
  }

  int64_t last_done_ = 0;
  int64_t last_total_ = 0;
};

TEST_F(BagExtractionTest, PlanarOdometryRawImagesAndCameraInfo) {
  const nlohmann::json& expected = Expected()["planar.bag"];
  const BagExtractionSummary summary = Extract("planar.bag", {});
  EXPECT_EQ(summary.topics.cameras[0].image, "/cam/image_raw");
  EXPECT_EQ(summary.topics.odometry, "/odom");
  EXPECT_EQ(summary.topics.cameras[0].camera_info, "/cam/camera_info");
  EXPECT_EQ(summary.cameras[0].images.used, 10);
  EXPECT_EQ(summary.odometry.used, 60);
  EXPECT_EQ(summary.odometry_file, "odometry.csv");
  EXPECT_TRUE(summary.planar);
  EXPECT_NEAR(summary.cameras[0].images.rate_hz, 10.0, 1e-6);
  EXPECT_NEAR(summary.odometry.rate_hz, 50.0, 1e-6);
  EXPECT_NEAR(
      summary.cameras[0].images.mean_abs_header_minus_receive_s, 0.015, 1e-9);
  EXPECT_NEAR(summary.odometry.mean_abs_header_minus_receive_s, 0.004, 1e-9);
  EXPECT_TRUE(summary.warnings.empty()) << summary.warnings.front();
  // Camera info, images and odometry; not the unrelated topic.
  EXPECT_EQ(last_done_, 3 + 10 + 60);
  EXPECT_EQ(last_total_, 3 + 10 + 60);

  const std::map<std::string, int64_t> stamps = ReadImageTimestampsCsv(
      Path("out/image_timestamps.csv"), TimeUnit::kSeconds);
  ASSERT_EQ(stamps.size(), expected["images"].size());
  for (const nlohmann::json& image : expected["images"]) {
    const int64_t header_ns = image["header_ns"];
    const std::string name = std::to_string(header_ns) + ".png";
    ASSERT_EQ(stamps.count(name), 1u) << name;
    EXPECT_EQ(stamps.at(name), header_ns);
    const cv::Mat pixels =
        cv::imread(Path("out/images/" + name), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(pixels.type(), CV_8UC3) << name;
    ASSERT_EQ(pixels.cols, 8);
    ASSERT_EQ(pixels.rows, 6);
    for (const nlohmann::json& sample : image["pixels"]) {
      const cv::Vec3b bgr =
          pixels.at<cv::Vec3b>(sample[0].get<int>(), sample[1].get<int>());
      EXPECT_EQ(bgr[2], sample[2].get<int>()) << name;
      EXPECT_EQ(bgr[1], sample[3].get<int>()) << name;
      EXPECT_EQ(bgr[0], sample[4].get<int>()) << name;
    }
  }

  const Trajectory odometry =
      ReadOdometryCsv(Path("out/odometry.csv"), TimeUnit::kSeconds);
  ASSERT_EQ(odometry.poses.size(), expected["odometry"].size());
  for (size_t i = 0; i < odometry.poses.size(); ++i) {
    const nlohmann::json& pose = expected["odometry"][i];
    EXPECT_EQ(odometry.poses[i].stamp_ns, pose["stamp_ns"].get<int64_t>());
    EXPECT_NEAR(odometry.poses[i].world_from_sensor.translation.x(),
                pose["position"][0].get<double>(),
                1e-12);
    EXPECT_NEAR(odometry.poses[i].world_from_sensor.translation.y(),
                pose["position"][1].get<double>(),
                1e-12);
    EXPECT_NEAR(YawAboutZ(odometry.poses[i].world_from_sensor.rotation),
                pose["yaw"].get<double>(),
                1e-12);
  }

  const ColmapCamera camera = ReadCamera("out");
  const nlohmann::json& info = expected["camera"];
  EXPECT_EQ(camera.model, ColmapCameraModel::kOpenCV);
  EXPECT_EQ(camera.width, 8u);
  EXPECT_EQ(camera.height, 6u);
  ASSERT_EQ(camera.params.size(), 8u);
  EXPECT_DOUBLE_EQ(camera.params[0], info["k"][0].get<double>());
  EXPECT_DOUBLE_EQ(camera.params[1], info["k"][4].get<double>());
  EXPECT_DOUBLE_EQ(camera.params[2], info["k"][2].get<double>() + 0.5);
  EXPECT_DOUBLE_EQ(camera.params[3], info["k"][5].get<double>() + 0.5);
  for (int i = 0; i < 4; ++i) {
    EXPECT_DOUBLE_EQ(camera.params[4 + i], info["d"][i].get<double>());
  }
}

TEST_F(BagExtractionTest, ReceiveTimesName) {
  const nlohmann::json& expected = Expected()["planar.bag"];
  BagExtractionOptions options;
  options.time = BagTime::kReceive;
  Extract("planar.bag", options);
  const std::map<std::string, int64_t> stamps = ReadImageTimestampsCsv(
      Path("out/image_timestamps.csv"), TimeUnit::kSeconds);
  for (const nlohmann::json& image : expected["images"]) {
    const int64_t receive_ns = image["receive_ns"];
    const std::string name = std::to_string(receive_ns) + ".png";
    ASSERT_EQ(stamps.count(name), 1u) << name;
    EXPECT_EQ(stamps.at(name), receive_ns);
  }
  const Trajectory odometry =
      ReadOdometryCsv(Path("out/odometry.csv"), TimeUnit::kSeconds);
  ASSERT_FALSE(odometry.poses.empty());
  EXPECT_EQ(odometry.poses.back().stamp_ns,
            expected["odometry"].back()["receive_ns"].get<int64_t>());
}

TEST_F(BagExtractionTest, RefusesAFolderInUse) {
  Extract("planar.bag", {});
  const std::string error = FormatErrorOf([&] { Extract("planar.bag", {}); });
  EXPECT_TRUE(Contains(error, Path("out") + ": ")) << error;
  EXPECT_TRUE(Contains(error, "not empty")) << error;
}

TEST_F(BagExtractionTest, Se3OdometryAndCompressedImages) {
  const nlohmann::json& expected = Expected()["se3.bag"];
  const BagExtractionSummary summary = Extract("se3.bag", {});
  EXPECT_TRUE(summary.topics.cameras[0].image_compressed);
  EXPECT_FALSE(summary.planar);
  EXPECT_EQ(summary.odometry_file, "odometry.tum");
  // The images arrive 30 ms after their stamps; the odometry every 20 ms.
  ASSERT_EQ(summary.warnings.size(), 1u);
  EXPECT_TRUE(Contains(summary.warnings[0], "/cam/image_raw/compressed: "))
      << summary.warnings[0];
  EXPECT_TRUE(Contains(summary.warnings[0], "30.0 ms")) << summary.warnings[0];

  for (const nlohmann::json& image : expected["images"]) {
    // PNG bytes, whatever the format string says.
    const std::string name =
        std::to_string(image["header_ns"].get<int64_t>()) + ".png";
    const std::string bytes = ReadFile(dir_ / "out" / "images" / name);
    std::string hex;
    for (const unsigned char c : bytes) {
      static const char* digits = "0123456789abcdef";
      hex += digits[c >> 4];
      hex += digits[c & 15];
    }
    EXPECT_EQ(hex, image["bytes"].get<std::string>()) << name;
  }

  const Trajectory odometry =
      ReadTumTrajectory(Path("out/odometry.tum"), TimeUnit::kSeconds);
  ASSERT_EQ(odometry.poses.size(), expected["odometry"].size());
  for (size_t i = 0; i < odometry.poses.size(); ++i) {
    const nlohmann::json& pose = expected["odometry"][i];
    const Rigid3d& read = odometry.poses[i].world_from_sensor;
    EXPECT_EQ(odometry.poses[i].stamp_ns, pose["stamp_ns"].get<int64_t>());
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_NEAR(
          read.translation[axis], pose["position"][axis].get<double>(), 1e-12);
    }
    const Eigen::Quaterniond given(pose["xyzw"][3].get<double>(),
                                   pose["xyzw"][0].get<double>(),
                                   pose["xyzw"][1].get<double>(),
                                   pose["xyzw"][2].get<double>());
    EXPECT_LT(RotationAngle(given.inverse() * read.rotation), 1e-9);
  }

  const ColmapCamera camera = ReadCamera("out");
  EXPECT_EQ(camera.model, ColmapCameraModel::kOpenCVFisheye);
  EXPECT_EQ(camera.width, 4u);
  EXPECT_EQ(camera.height, 3u);
}

TEST_F(BagExtractionTest, WheelJointStatesAndBayerImages) {
  const nlohmann::json& expected = Expected()["wheels.bag"];
  EXPECT_THROW(Extract("wheels.bag", {}, "no_radius"), std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir_ / "no_radius"));  // nothing created

  BagExtractionOptions options;
  options.wheel_radius_m = 0.1;
  const BagExtractionSummary summary = Extract("wheels.bag", options);
  EXPECT_TRUE(summary.topics.odometry_joint_state);
  EXPECT_EQ(summary.odometry_file, "wheels.csv");
  EXPECT_EQ(summary.left_wheel_joint, "base_Left_wheel");
  EXPECT_EQ(summary.right_wheel_joint, "base_Right_wheel");
  EXPECT_EQ(summary.odometry.used, 40);
  EXPECT_FALSE(summary.cameras[0].camera.has_value());
  EXPECT_EQ(summary.cameras[0].images.messages, 5);
  EXPECT_EQ(summary.cameras[0].images.used, 4);
  EXPECT_EQ(summary.cameras[0].images.duplicate_stamps, 1);
  ASSERT_EQ(summary.warnings.size(), 2u);
  EXPECT_TRUE(Contains(summary.warnings[0], "40 joint states"))
      << summary.warnings[0];
  EXPECT_TRUE(Contains(summary.warnings[1], "/cam/image_raw: 1 messages"))
      << summary.warnings[1];

  // Integrated by odomcal's wheel-travel reader: the heading turned by
  // (right - left) * radius / track.
  WheelTravelOptions wheels;
  wheels.track_m = 0.4;
  const Trajectory odometry = ReadOdometry(Path("out/wheels.csv"),
                                           OdometryFormat::kAuto,
                                           TimeUnit::kSeconds,
                                           false,
                                           wheels);
  const nlohmann::json& joints = expected["joints"];
  ASSERT_EQ(odometry.poses.size(), joints.size());
  for (size_t i = 0; i < joints.size(); ++i) {
    EXPECT_EQ(odometry.poses[i].stamp_ns, joints[i]["stamp_ns"].get<int64_t>());
  }
  const double turned = (joints.back()["right_rad"].get<double>() -
                         joints.back()["left_rad"].get<double>() -
                         joints[0]["right_rad"].get<double>() +
                         joints[0]["left_rad"].get<double>()) *
                        0.1 / 0.4;
  EXPECT_NEAR(YawAboutZ(odometry.poses.back().world_from_sensor.rotation),
              turned,
              1e-9);

  const nlohmann::json& rgb = expected["rgb"];
  for (const nlohmann::json& image : expected["images"]) {
    const std::string name =
        std::to_string(image["header_ns"].get<int64_t>()) + ".png";
    const cv::Mat pixels =
        cv::imread(Path("out/images/" + name), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(pixels.type(), CV_8UC3) << name;
    const cv::Vec3b bgr = pixels.at<cv::Vec3b>(3, 4);
    EXPECT_EQ(bgr[2], rgb[0].get<int>());
    EXPECT_EQ(bgr[1], rgb[1].get<int>());
    EXPECT_EQ(bgr[0], rgb[2].get<int>());
  }
}

TEST_F(BagExtractionTest, StampsGoingBackAreRefused) {
  const nlohmann::json& expected = Expected()["backwards.bag"];
  const std::string error =
      FormatErrorOf([&] { Extract("backwards.bag", {}); });
  EXPECT_TRUE(Contains(error, BagPath("backwards.bag") + ": /odom: ")) << error;
  EXPECT_TRUE(
      Contains(error, std::to_string(expected["back_ns"].get<int64_t>())))
      << error;
  EXPECT_TRUE(
      Contains(error, std::to_string(expected["previous_ns"].get<int64_t>())))
      << error;
}

// Every compressed image is decoded, not only the first: COLMAP would skip
// one that does not decode without a word.
TEST_F(BagExtractionTest, ACompressedImageThatDoesNotDecodeIsRefused) {
  const nlohmann::json& expected = Expected()["broken.bag"];
  const std::string error = FormatErrorOf([&] { Extract("broken.bag", {}); });
  EXPECT_TRUE(
      Contains(error, BagPath("broken.bag") + ": /cam/image_raw/compressed: "))
      << error;
  EXPECT_TRUE(Contains(
      error,
      "the image at " + std::to_string(expected["broken_ns"].get<int64_t>()) +
          " ns"))
      << error;
  EXPECT_TRUE(Contains(error, "does not decode")) << error;
}

TEST_F(BagExtractionTest, UnstampedImagesNeedReceiveTimes) {
  const nlohmann::json& expected = Expected()["unstamped.bag"];
  const std::string error =
      FormatErrorOf([&] { Extract("unstamped.bag", {}); });
  EXPECT_TRUE(Contains(error, "/cam/image_raw: ")) << error;
  EXPECT_TRUE(Contains(error, "--bag_time receive")) << error;

  BagExtractionOptions options;
  options.time = BagTime::kReceive;
  Extract("unstamped.bag", options, "receive");
  for (const nlohmann::json& receive : expected["receive_ns"]) {
    EXPECT_TRUE(fs::exists(dir_ / "receive" / "images" /
                           (std::to_string(receive.get<int64_t>()) + ".png")));
  }
}

TEST_F(BagExtractionTest, RegionOfInterestIsRefused) {
  const std::string error = FormatErrorOf([&] { Extract("roi.bag", {}); });
  EXPECT_TRUE(Contains(error, BagPath("roi.bag") + ": /cam/camera_info: roi: "))
      << error;
  EXPECT_TRUE(Contains(error, "x_offset 1, y_offset 2, 4 x 3")) << error;
}

TEST_F(BagExtractionTest, CameraInfoMustFitTheImages) {
  const std::string error = FormatErrorOf([&] { Extract("size.bag", {}); });
  EXPECT_TRUE(Contains(
      error, BagPath("size.bag") + ": /cam/camera_info: width/height: "))
      << error;
  EXPECT_TRUE(Contains(error, "10 x 6")) << error;
  EXPECT_TRUE(Contains(error, "8 x 6")) << error;
}

// Three image topics of one bag: a rig, each camera's images in
// images/<camera>/ at its own rate and size, one image_timestamps.csv, and
// cameras.txt with the cameras that have a CameraInfo.
TEST_F(BagExtractionTest, RigOfThreeCamerasFromOneBag) {
  const nlohmann::json& expected = Expected()["rig.bag"];
  BagExtractionOptions options;
  options.image_topics = {
      "/left/image_raw", "/right/image_raw/compressed", "/rear/image_raw"};
  const BagExtractionSummary summary = Extract("rig.bag", options);
  ASSERT_TRUE(summary.topics.rig);
  ASSERT_EQ(summary.cameras.size(), 3u);
  const std::vector<std::string> names = {"left", "rear", "right"};
  const std::map<std::string, int64_t> stamps = ReadImageTimestampsCsv(
      Path("out/image_timestamps.csv"), TimeUnit::kSeconds);
  size_t images = 0;
  for (size_t k = 0; k < names.size(); ++k) {
    const std::string& name = names[k];
    SCOPED_TRACE(name);
    const CameraExtractionSummary& camera = summary.cameras[k];
    EXPECT_EQ(camera.name, name);
    EXPECT_EQ(camera.images.used, static_cast<int64_t>(expected[name].size()));
    for (const nlohmann::json& stamp : expected[name]) {
      const std::string file =
          name + "/" + std::to_string(stamp.get<int64_t>()) + ".png";
      ASSERT_EQ(stamps.count(file), 1u) << file;
      EXPECT_EQ(stamps.at(file), stamp.get<int64_t>());
      const cv::Mat pixels =
          cv::imread(Path("out/images/" + file), cv::IMREAD_UNCHANGED);
      EXPECT_EQ(pixels.cols, name == "right" ? 4 : 8) << file;
      EXPECT_EQ(pixels.rows, name == "right" ? 3 : 6) << file;
      ++images;
    }
  }
  EXPECT_EQ(stamps.size(), images);
  EXPECT_FALSE(summary.cameras[1].camera.has_value());  // rear: none
  EXPECT_FALSE(fs::exists(Path("out/camera.txt")));

  // cameras.txt as a COLMAP text model: left (camera_id 1) and right (3).
  const fs::path model = dir_ / "model";
  fs::create_directories(model);
  fs::copy_file(dir_ / "out" / "cameras.txt", model / "cameras.txt");
  std::ofstream(model / "images.txt") << "";
  std::ofstream(model / "points3D.txt") << "";
  const ColmapModel read = ReadColmapModel(model.string());
  ASSERT_EQ(read.cameras.size(), 2u);
  const ColmapCamera& left = read.cameras.at(1);
  EXPECT_EQ(left.model, ColmapCameraModel::kOpenCV);
  EXPECT_EQ(left.width, 8u);
  const nlohmann::json& k_left = expected["cameras"]["left"]["k"];
  EXPECT_DOUBLE_EQ(left.params[2], k_left[2].get<double>() + 0.5);
  const ColmapCamera& right = read.cameras.at(3);
  EXPECT_EQ(right.model, ColmapCameraModel::kPinhole);
  EXPECT_EQ(right.width, 4u);
  const nlohmann::json& k_right = expected["cameras"]["right"]["k"];
  EXPECT_DOUBLE_EQ(right.params[0], k_right[0].get<double>());
  EXPECT_DOUBLE_EQ(right.params[3], k_right[5].get<double>() + 0.5);
  EXPECT_TRUE(Contains(ReadFile(dir_ / "out" / "cameras.txt"),
                       "--camera_params right=3.5,3.25,2,1.5"));
}

}  // namespace
}  // namespace odomcal::bag
