// `odomcal calibrate --camera NAME=PATH ...` end to end: a simulated robot
// with several cameras, each seen by its own "SfM run" (its own frame, scale,
// rate, phase and clock offset), calibrated against one wheel odometry.
// Checks every camera's extrinsic and every camera-to-camera transform
// against the truth within the stated 3 sigma, a camera that cannot be
// calibrated named with its own status while the others are written, and
// the flag errors (docs/robustness.md).

#include "odomcal/adapters/trajectory_io.h"
#include "odomcal/datasets/simulation/camera_mount.h"
#include "odomcal/datasets/simulation/drive_simulator.h"
#include "odomcal/solver/angles.h"
#include "odomcal/tests/rig_expectations.h"
#include "odomcal/tests/test_files.h"
#include "odomcal/tests/test_seed.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace odomcal {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct CommandResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

// One camera of the simulated rig.
struct SimulatedCamera {
  std::string name;
  Rigid3d odom_from_cam;
  double rate_hz = 5.0;
  double phase_s = 0.0;         // first frame after the drive's start
  double clock_offset_s = 0.0;  // its stamps are true time - this
  double metric_scale = 1.0;    // metres per unit of its "SfM run"
  double duration_s = 1e9;      // frames only this long after the start
};

int LineCount(const std::string& text) {
  int lines = 0;
  for (const char c : text) lines += c == '\n';
  return lines;
}

class RigCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(::testing::TempDir()) /
           (std::string("odomcal_rig_cli_") + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string Path(const std::string& name) const {
    return (dir_ / name).string();
  }

  CommandResult Run(const std::string& arguments) const {
    const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
    const std::string command = std::string(ODOMCAL_EXECUTABLE) + " " +
                                arguments + " > " + out.string() + " 2> " +
                                err.string();
    const int status = std::system(command.c_str());
    CommandResult result;
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    result.out = ReadFile(out);
    result.err = ReadFile(err);
    return result;
  }

  // Writes odometry.csv and NAME.tum per camera: each camera's poses from
  // the true robot motion at its own rate and phase, in its own random
  // similarity frame, with pose noise.
  void WriteRig(uint64_t seed, const std::vector<SimulatedCamera>& cameras) {
    DriveSimulatorOptions options;
    options.seed = seed;
    options.duration_s = 90.0;
    options.odometry_rate_hz = 200.0;
    options.wheel_scale_error_left = 0.002;
    options.wheel_scale_error_right = -0.002;
    options.yaw_rate_bias_radps = 0.001;
    const SimulatedDrive drive = SimulateDrive(options);
    WriteOdometryCsv(drive.odometry, Path("odometry.csv"));
    std::mt19937_64 rng(seed * 7919 + 1);
    std::normal_distribution<double> gauss(0.0, 1.0);
    const int64_t start_ns = drive.true_odometry.poses.front().stamp_ns;
    for (const SimulatedCamera& camera : cameras) {
      const Rigid3d sfm_from_origin(
          Eigen::Quaterniond(gauss(rng), gauss(rng), gauss(rng), gauss(rng))
              .normalized(),
          Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)));
      Trajectory trajectory;
      const int64_t period_ns = std::llround(1e9 / camera.rate_hz);
      const int64_t phase_ns = std::llround(1e9 * camera.phase_s);
      for (const StampedPose& pose : drive.true_odometry.poses) {
        const int64_t since_start_ns = pose.stamp_ns - start_ns - phase_ns;
        if (since_start_ns < 0 || since_start_ns % period_ns != 0 ||
            since_start_ns > std::llround(1e9 * camera.duration_s)) {
          continue;
        }
        const Rigid3d sfm_from_cam =
            sfm_from_origin * pose.world_from_sensor * camera.odom_from_cam;
        const Eigen::Vector3d rotation_noise(
            gauss(rng), gauss(rng), gauss(rng));
        const Eigen::Vector3d position_noise(
            gauss(rng), gauss(rng), gauss(rng));
        trajectory.poses.push_back(
            {pose.stamp_ns - std::llround(1e9 * camera.clock_offset_s),
             Rigid3d((ExpRotation(rotation_noise * 0.02 * kDegToRad) *
                      sfm_from_cam.rotation)
                         .normalized(),
                     sfm_from_cam.translation / camera.metric_scale +
                         0.001 * position_noise)});
      }
      WriteTumTrajectory(trajectory, Path(camera.name + ".tum"));
    }
  }

  std::string RigArguments(const std::vector<SimulatedCamera>& cameras) const {
    std::string arguments = "calibrate --odometry " + Path("odometry.csv") +
                            " --output " + Path("rig.json") +
                            " --fixed_translation_z_m 0.5";
    for (const SimulatedCamera& camera : cameras) {
      arguments +=
          " --camera " + camera.name + "=" + Path(camera.name + ".tum");
    }
    return arguments;
  }

  // Each `run` of `cases` (arguments, message) exits 2 with the one line
  // "odomcal run: error: <message>" and leaves no workspace.
  void ExpectRunErrors(
      const std::vector<std::pair<std::string, std::string>>& cases) const {
    for (const auto& [arguments, message] : cases) {
      SCOPED_TRACE(arguments);
      const CommandResult run = Run(arguments);
      EXPECT_EQ(run.exit_code, 2) << run.out << run.err;
      EXPECT_EQ(run.err, "odomcal run: error: " + message + "\n");
      EXPECT_FALSE(fs::exists(Path("ws")));
    }
  }

  fs::path dir_;
};

// All cameras at 0.5 m: z is held at --fixed_translation_z_m under planar
// driving, so the pairs' height differences are the held ones.
std::vector<SimulatedCamera> ThreeCameraRig() {
  return {
      {"front",
       MakeCameraMount(0.0, 10.0, 0.0, {0.30, 0.00, 0.50}),
       5.0,
       0.0,
       0.0,
       0.37},
      {"rear",
       MakeCameraMount(180.0, 15.0, 0.0, {-0.20, 0.05, 0.50}),
       4.0,
       0.03,
       0.02,
       1.9},
      {"left",
       MakeCameraMount(90.0, 5.0, 2.0, {0.05, 0.20, 0.50}),
       8.0,
       0.115,
       -0.015,
       0.8},
  };
}

TEST_F(RigCli, EveryCameraAndPairWithinThreeSigma) {
  const uint64_t seed = TestSeed(31);
  SCOPED_TRACE("seed " + std::to_string(seed));
  const std::vector<SimulatedCamera> rig = ThreeCameraRig();
  WriteRig(seed, rig);
  const CommandResult run = Run(RigArguments(rig) + " --reference_camera rear");
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const json result = json::parse(ReadFile(Path("rig.json")));
  EXPECT_EQ(result["reference_camera"], "rear");
  ASSERT_EQ(result["cameras"].size(), 3u);
  for (size_t k = 0; k < rig.size(); ++k) {
    const json& camera = result["cameras"][k];
    SCOPED_TRACE(rig[k].name);
    EXPECT_EQ(camera["name"], rig[k].name);
    ASSERT_EQ(camera["status"], "success") << camera["reason"];
    ExpectWithinThreeSigma("camera",
                           rig[k].odom_from_cam,
                           camera["odom_from_cam"],
                           camera["covariance"],
                           /*z_held=*/true);
    EXPECT_NEAR(camera["metric_scale"].get<double>(),
                rig[k].metric_scale,
                3.0 * camera["stddev"]["metric_scales_rel"][0].get<double>() *
                    rig[k].metric_scale);
    EXPECT_NEAR(camera["camera_time_offset_s"].get<double>(),
                rig[k].clock_offset_s,
                3.0 * camera["stddev"]["camera_time_offset_s"].get<double>());
  }
  // The top level is the reference camera's.
  EXPECT_EQ(result["odom_from_cam"], result["cameras"][1]["odom_from_cam"]);
  ASSERT_EQ(result["camera_pairs"].size(), 3u);
  for (const json& pair : result["camera_pairs"]) {
    const int a = pair["camera_a"] == "front" ? 0 : 1;
    const int b = pair["camera_b"] == "rear" ? 1 : 2;
    SCOPED_TRACE(rig[b].name + "_from_" + rig[a].name);
    ExpectWithinThreeSigma("pair",
                           Inverse(rig[b].odom_from_cam) * rig[a].odom_from_cam,
                           pair["camb_from_cama"],
                           pair["covariance"],
                           /*z_held=*/false);
    EXPECT_TRUE(pair["odom_offset_z_held"].get<bool>());
  }
  // One joint per camera in the robot outputs.
  const std::string urdf = ReadFile(Path("rig.urdf"));
  for (const SimulatedCamera& camera : rig) {
    EXPECT_NE(
        urdf.find("base_link_to_" + camera.name + "_camera_optical_frame"),
        std::string::npos)
        << urdf;
  }
}

TEST_F(RigCli, CameraWithTooFewPosesIsNamedAndTheOthersAreWritten) {
  const uint64_t seed = TestSeed(32);
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::vector<SimulatedCamera> rig = ThreeCameraRig();
  rig[2].duration_s = 1.0;  // "left" stops after its first seconds
  WriteRig(seed, rig);
  const CommandResult run = Run(RigArguments(rig));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.err.find("warning: camera left not calibrated"),
            std::string::npos)
      << run.err;
  const json result = json::parse(ReadFile(Path("rig.json")));
  EXPECT_EQ(result["reference_camera"], "front");
  EXPECT_EQ(result["cameras"][0]["status"], "success");
  EXPECT_EQ(result["cameras"][1]["status"], "success");
  EXPECT_NE(result["cameras"][2]["status"], "success");
  EXPECT_FALSE(result["cameras"][2]["reason"].get<std::string>().empty());
  EXPECT_TRUE(result["cameras"][2]["odom_from_cam"].is_null() ||
              !result["cameras"][2]["calibrated"].get<bool>());
  ASSERT_EQ(result["camera_pairs"].size(), 1u);
  EXPECT_EQ(result["camera_pairs"][0]["camera_a"], "front");
  EXPECT_EQ(result["camera_pairs"][0]["camera_b"], "rear");
  bool warned = false;
  for (const json& warning : result["warnings"]) {
    warned |= warning.get<std::string>().rfind("camera left not", 0) == 0;
  }
  EXPECT_TRUE(warned) << result["warnings"];
  const std::string urdf = ReadFile(Path("rig.urdf"));
  EXPECT_NE(urdf.find("rear_camera_optical_frame"), std::string::npos);
  EXPECT_EQ(urdf.find("left_camera_optical_frame"), std::string::npos);
}

// Poses whose time stamps miss the odometry (another clock, 5000 s off):
// that camera's input error, the other camera calibrated.
TEST_F(RigCli, CameraOutsideTheOdometrysTimeIsAnInputErrorOfItsOwn) {
  std::vector<SimulatedCamera> rig = ThreeCameraRig();
  rig.resize(2);
  rig[1].clock_offset_s = 5000.0;
  WriteRig(TestSeed(35), rig);
  const CommandResult run = Run(RigArguments(rig));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const json result = json::parse(ReadFile(Path("rig.json")));
  EXPECT_EQ(result["cameras"][0]["status"], "success");
  EXPECT_EQ(result["cameras"][1]["status"], "input_error");
  EXPECT_NE(result["cameras"][1]["reason"].get<std::string>().find(
                "no camera timestamp falls inside the odometry"),
            std::string::npos)
      << result["cameras"][1]["reason"];
  EXPECT_TRUE(result["cameras"][1]["odom_from_cam"].is_null());
  EXPECT_TRUE(result["camera_pairs"].empty());
  EXPECT_NE(run.err.find("warning: camera rear not calibrated (input_error)"),
            std::string::npos)
      << run.err;
}

TEST_F(RigCli, NoCameraCalibratedExitsThree) {
  std::vector<SimulatedCamera> rig = ThreeCameraRig();
  rig.resize(2);
  rig[0].duration_s = 1.0;
  rig[1].duration_s = 1.0;
  WriteRig(TestSeed(33), rig);
  const CommandResult run = Run(RigArguments(rig));
  EXPECT_EQ(run.exit_code, 3) << run.out << run.err;
  const json result = json::parse(ReadFile(Path("rig.json")));
  EXPECT_NE(result["cameras"][0]["status"], "success");
  EXPECT_NE(result["cameras"][1]["status"], "success");
  EXPECT_TRUE(result["camera_pairs"].empty());
}

TEST_F(RigCli, BadCameraFlagsGiveOneLineNamingTheFlag) {
  std::vector<SimulatedCamera> rig = ThreeCameraRig();
  rig.resize(2);
  WriteRig(TestSeed(34), rig);
  const std::string base = "calibrate --odometry " + Path("odometry.csv") +
                           " --output " + Path("r.json");
  const std::string front = Path("front.tum"), rear = Path("rear.tum");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {base + " --camera front=" + front + " --camera rear=" + front,
       "odomcal calibrate: error: --camera 'rear=" + front + "': the file " +
           front + " is given twice"},
      {base + " --camera =" + front,
       "odomcal calibrate: error: --camera '=" + front +
           "': the camera name before '=' is empty"},
      {base + " --camera " + front,
       "odomcal calibrate: error: --camera '" + front +
           "': expected NAME=PATH"},
      {base + " --camera 'front cam'=" + front,
       "odomcal calibrate: error: --camera 'front cam=" + front +
           "': a camera name is 1-100 characters of A-Z a-z 0-9 _ - ."},
      {base + " --camera front=" + Path("missing.tum"),
       "odomcal calibrate: error: --camera front=" + Path("missing.tum") +
           ": no such file"},
      {base + " --camera front=" + front + " --camera rear=" + rear +
           " --reference_camera side",
       "odomcal calibrate: error: --reference_camera 'side' names no camera "
       "given with --camera (front, rear)"},
  };
  for (const auto& [arguments, line] : cases) {
    SCOPED_TRACE(arguments);
    const CommandResult run = Run(arguments);
    EXPECT_EQ(run.exit_code, 2) << run.out << run.err;
    EXPECT_EQ(run.err, line + "\n");
    EXPECT_FALSE(fs::exists(Path("r.json")));
  }
  // Mixed forms, and --reference_camera alone, are refused by the parser.
  for (const std::string& arguments :
       {base + " --camera front=" + front + " --camera_poses " + rear,
        base + " --camera_poses " + rear + " --reference_camera front",
        base}) {
    SCOPED_TRACE(arguments);
    const CommandResult run = Run(arguments);
    EXPECT_EQ(run.exit_code, 2) << run.out << run.err;
    EXPECT_EQ(LineCount(run.err), 1) << run.err;
    EXPECT_EQ(run.err.rfind("odomcal calibrate: error: ", 0), 0u) << run.err;
  }
}

}  // namespace
}  // namespace odomcal

namespace odomcal {
namespace {

// `run --rig`'s input errors, each one line naming the flag or folder,
// before any COLMAP stage (docs/robustness.md).
TEST_F(RigCli, RunRigInputErrorsGiveOneLine) {
  WriteRig(TestSeed(36), ThreeCameraRig());
  const fs::path images = dir_ / "images";
  for (const char* camera : {"front", "rear"}) {
    fs::create_directories(images / camera);
    std::ofstream(images / camera / "1700000000000000000.png") << "not read";
  }
  const std::string base = "run --rig --image_path " + images.string() +
                           " --odometry " + Path("odometry.csv") +
                           " --workspace_path " + Path("ws");
  const std::string error = "odomcal run: error: ";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {base + " --camera_params side=1,2,3,4",
       "--camera_params 'side=1,2,3,4': no camera 'side' (the cameras of "
       "--image_path: front, rear)"},
      {base + " --camera_params front=1,2,3,4 --camera_params front=1,2,3,5",
       "--camera_params 'front=1,2,3,5': camera 'front' given twice"},
      {base + " --camera_params 1,2,3,4 --camera_params front=1,2,3,5",
       "--camera_params: give either one PARAMS for every camera or "
       "NAME=PARAMS per camera, not both"},
      {base + " --reference_camera side",
       "--reference_camera 'side' names no camera sub-folder of --image_path "
       "(its cameras: front, rear)"},
      {"run --image_path " + images.string() + " --odometry " +
           Path("odometry.csv") + " --workspace_path " + Path("ws") +
           " --camera_params 1,2,3,4 --camera_params 5,6,7,8",
       "--camera_params is given 2 times: one camera takes one (several "
       "cameras: --rig)"},
  };
  ExpectRunErrors(cases);
  // A camera folder without images; an image in no camera's folder.
  fs::create_directories(images / "side");
  CommandResult run = Run(base);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(run.err,
            error + "--rig: camera sub-folder " + (images / "side").string() +
                " holds no images (.png, .jpg, .jpeg, .bmp, .tif)\n");
  fs::remove(images / "side");
  std::ofstream(images / "1700000000000000000.png") << "not read";
  run = Run(base);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(run.err.rfind(error + "--rig: " +
                              (images / "1700000000000000000.png").string() +
                              " lies in no camera sub-folder",
                          0),
            0u)
      << run.err;
  EXPECT_FALSE(fs::exists(Path("ws")));
}

// A bag with several image topics through `run --bag` (rig.bag of
// tests/fixtures/bags/make_extract_bags.py: left with a plumb_bob
// CameraInfo, right with a distortion-free one, rear without). Its drive is
// 1.2 s of one turn, so every camera is refused before COLMAP: what is
// checked is the rig the bag becomes, not a calibration.
std::string RigBag() {
  return (fs::path(ODOMCAL_EXTRACT_FIXTURE_DIR) / "rig.bag").string();
}

TEST_F(RigCli, RunBagWithSeveralImageTopicsTakesEachCamerasCameraInfo) {
  const CommandResult run =
      Run("run --bag " + RigBag() +
          " --image_topic /left/image_raw --image_topic "
          "/right/image_raw/compressed --image_topic /rear/image_raw "
          "--camera_model PINHOLE --camera_params rear=8,8,4,3 "
          "--reference_camera right --colmap_path " +
          Path("no_colmap") + " --workspace_path " + Path("ws"));
  EXPECT_EQ(run.exit_code, 3) << run.out << run.err;
  EXPECT_NE(run.out.find("topics: 3 cameras left (images /left/image_raw, "
                         "camera info /left/camera_info), rear (images "
                         "/rear/image_raw, no camera info (give "
                         "--camera_params rear=PARAMS)), right (images "
                         "/right/image_raw/compressed, camera info "
                         "/right/camera_info), odometry /odom"),
            std::string::npos)
      << run.out;
  for (const char* name : {"left", "rear", "right"}) {
    EXPECT_TRUE(fs::is_directory(dir_ / "ws" / "bag_inputs" / "images" / name))
        << name;
  }
  const json result = json::parse(ReadFile(dir_ / "ws" / "calibration.json"));
  EXPECT_EQ(result["reference_camera"], "right");
  ASSERT_EQ(result["cameras"].size(), 3u);
  EXPECT_EQ(result["inputs"]["rig"], true);
  EXPECT_EQ(result["inputs"]["bag"], RigBag());
  EXPECT_EQ(result["options"]["bag"]["image_topic"],
            json::array({"/left/image_raw",
                         "/right/image_raw/compressed",
                         "/rear/image_raw"}));
  // Each camera's intrinsics: its CameraInfo's (model and COLMAP's pixel
  // centre, cx + 0.5), or the --camera_params given for it.
  const std::map<std::string, std::pair<std::string, std::string>> cameras = {
      {"left", {"OPENCV", "7.5,7.25,3.75,3.25,-0.21,0.043,0.0011,-0.0007"}},
      {"rear", {"PINHOLE", "8,8,4,3"}},
      {"right", {"PINHOLE", "3.5,3.25,2,1.5"}},
  };
  for (const auto& [name, camera] : cameras) {
    SCOPED_TRACE(name);
    const json own = json::parse(
        ReadFile(dir_ / "ws" / "cameras" / name / "calibration.json"));
    EXPECT_EQ(own["options"]["run"]["camera_model"], camera.first);
    EXPECT_EQ(own["options"]["run"]["camera_params"], camera.second);
    EXPECT_EQ(own["status"], "unobservable");
  }
}

// The rig's topic errors: one line naming the topic or flag, before the
// workspace is created (docs/robustness.md).
TEST_F(RigCli, BagRigInputErrorsGiveOneLine) {
  const std::string base = "run --bag " + RigBag() + " --workspace_path " +
                           Path("ws") + " --image_topic /left/image_raw";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {base + " --image_topic /front/image_raw",
       "--image_topic /front/image_raw is not in the bag; image topics: "
       "/left/image_raw (sensor_msgs/Image, 10 messages), "
       "/left/image_raw/compressed (sensor_msgs/CompressedImage, 10 "
       "messages), /rear/image_raw (sensor_msgs/Image, 4 messages), "
       "/right/image_raw/compressed (sensor_msgs/CompressedImage, 5 "
       "messages)"},
      {base + " --image_topic /rear/image_raw",
       "--image_topic /rear/image_raw (camera rear): the bag has no "
       "CameraInfo beside it (/rear/camera_info) and no --camera_params "
       "rear=PARAMS is given"},
      {base + " --image_topic /left/image_raw/compressed",
       "image topics /left/image_raw and /left/image_raw/compressed both "
       "make camera 'left' (a camera is named by its topic's namespace): "
       "give one of them, or name each with --image_topic NAME=TOPIC"},
      {"run --bag " + RigBag() + " --workspace_path " + Path("ws") + " --rig",
       "image topics /left/image_raw and /left/image_raw/compressed both "
       "make camera 'left' (a camera is named by its topic's namespace): "
       "give one of them, or name each with --image_topic NAME=TOPIC"},
      {base + " --image_topic /right/image_raw/compressed --camera_params "
              "side=1,2,3,4",
       "--camera_params 'side=1,2,3,4': no camera 'side' (the cameras of "
       "--bag: left, right)"},
      {base + " --image_topic /right/image_raw/compressed "
              "--reference_camera side",
       "--reference_camera 'side' names no camera of --bag (its cameras: "
       "left, right)"},
      {"run --bag " + RigBag() + " --workspace_path " + Path("ws") +
           " --reference_camera left",
       "--reference_camera requires --rig (or several --image_topic with "
       "--bag)"},
  };
  ExpectRunErrors(cases);
}

// `inspect` says what a rig run would take; `extract` with several
// --image_topic writes the rig layout and the `run --rig` command.
TEST_F(RigCli, InspectAndExtractABagWithSeveralImageTopics) {
  CommandResult run = Run("inspect --bag " + RigBag());
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("run --bag cannot choose by itself: the bag has 4 "
                         "image topics: "),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("pass --image_topic to choose one (several "
                         "--image_topic: a rig, one camera each)"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("run --bag --rig cannot choose by itself: image "
                         "topics /left/image_raw and "
                         "/left/image_raw/compressed both make camera 'left'"),
            std::string::npos)
      << run.out;
  const std::string two =
      " --image_topic /left/image_raw --image_topic "
      "/right/image_raw/compressed";
  run = Run("inspect --bag " + RigBag() + two);
  EXPECT_NE(run.out.find("run --bag would use: 2 cameras left (images "
                         "/left/image_raw, camera info /left/camera_info), "
                         "right (images /right/image_raw/compressed, camera "
                         "info /right/camera_info), odometry /odom\n"),
            std::string::npos)
      << run.out;

  run = Run("extract --bag " + RigBag() + two + " --output_path " +
            Path("inputs"));
  EXPECT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_EQ(fs::exists(dir_ / "inputs" / "images" / "left" /
                       "1690000000123456796.png"),
            true);
  EXPECT_EQ(fs::exists(dir_ / "inputs" / "images" / "right" /
                       "1690000000173456800.png"),
            true);
  const std::string times = ReadFile(dir_ / "inputs" / "image_timestamps.csv");
  EXPECT_NE(times.find("\nleft/1690000000123456796.png,1690000000.123456796\n"),
            std::string::npos)
      << times;
  EXPECT_NE(
      times.find("\nright/1690000000173456800.png,1690000000.173456800\n"),
      std::string::npos)
      << times;
  EXPECT_NE(ReadFile(dir_ / "inputs" / "cameras.txt")
                .find("\n2 PINHOLE 4 3 3.5 3.25 2 1.5\n"),
            std::string::npos);
  EXPECT_NE(run.out.find("  odomcal run --rig --image_path " + Path("inputs") +
                         "/images --image_timestamps "),
            std::string::npos)
      << run.out;
  // OPENCV and PINHOLE: run --rig takes one --camera_model.
  EXPECT_NE(run.out.find("run --rig takes one --camera_model and the "
                         "cameras' differ"),
            std::string::npos)
      << run.out;
}

}  // namespace
}  // namespace odomcal
