// End-to-end tests of the `odomcal` executable on generated input files:
// accuracy against the simulator's ground truth, statuses and exit codes,
// one-line errors on bad files, outputs that never clobber or touch inputs.

#include "odomcal/adapters/trajectory_io.h"
#include "odomcal/datasets/simulation/drive_simulator.h"
#include "odomcal/solver/angles.h"
#include "odomcal/tests/test_files.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
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

class OdomcalCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(::testing::TempDir()) /
           (std::string("odomcal_cli_") + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

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

  // Writes camera.tum and odometry.csv for a simulated drive.
  SimulatedDrive WriteDrive(const DriveSimulatorOptions& options) const {
    const SimulatedDrive drive = SimulateDrive(options);
    WriteTumTrajectory(drive.camera, (dir_ / "camera.tum").string());
    WriteOdometryCsv(drive.odometry, (dir_ / "odometry.csv").string());
    return drive;
  }

  std::string Path(const std::string& name) const {
    return (dir_ / name).string();
  }

  std::string BasicArguments() const {
    return "calibrate --camera_poses " + Path("camera.tum") + " --odometry " +
           Path("odometry.csv") + " --output " + Path("result.json");
  }

  fs::path dir_;
};

DriveSimulatorOptions RealisticDrive(uint64_t seed) {
  DriveSimulatorOptions options;
  options.seed = seed;
  options.duration_s = 90.0;
  options.wheel_scale_error_left = 0.002;
  options.wheel_scale_error_right = -0.002;
  options.yaw_rate_bias_radps = 0.001;
  options.camera_rotation_noise_deg = 0.02;
  options.camera_position_noise = 0.001;
  return options;
}

int LineCount(const std::string& text) {
  int lines = 0;
  for (const char c : text) lines += c == '\n';
  return lines;
}

TEST_F(OdomcalCli, CalibratesSimulatedDriveAccurately) {
  const SimulatedDrive drive = WriteDrive(RealisticDrive(11));
  const CommandResult run =
      Run(BasicArguments() + " --fixed_translation_z_m 0.4");
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("success"), std::string::npos);
  const json result = json::parse(ReadFile(Path("result.json")));
  EXPECT_EQ(result["status"], "success");
  EXPECT_EQ(result["schema_version"], 1);
  const auto& q = result["odom_from_cam"]["quaternion_wxyz"];
  const Eigen::Quaterniond estimate(q[0], q[1], q[2], q[3]);
  // 90 s of driving with 0.2 % wheel errors and 0.02 deg camera noise.
  EXPECT_LT(RotationAngle(estimate.conjugate() * drive.odom_from_cam.rotation) *
                kRadToDeg,
            0.1);
  const auto& t = result["odom_from_cam"]["translation_m"];
  EXPECT_NEAR(t[0].get<double>(), drive.odom_from_cam.translation.x(), 0.005);
  EXPECT_NEAR(t[1].get<double>(), drive.odom_from_cam.translation.y(), 0.005);
  EXPECT_DOUBLE_EQ(t[2].get<double>(), 0.4);
  EXPECT_NEAR(
      result["metric_scale"].get<double>() / drive.metric_scale, 1.0, 0.005);
  EXPECT_EQ(result["unobservable"], json::array({"translation_z"}));
  EXPECT_EQ(result["covariance"]["order"],
            json::array({"rx", "ry", "rz", "tx", "ty", "s_0"}));
  EXPECT_EQ(result["diagnostics"]["inlier_mask"].size(),
            result["diagnostics"]["num_pairs_in"].get<size_t>());

  // The YAML beside it is OpenCV-readable and carries the same matrix.
  cv::FileStorage yaml(Path("result.yaml"), cv::FileStorage::READ);
  ASSERT_TRUE(yaml.isOpened());
  cv::Mat matrix;
  yaml["odom_from_cam"] >> matrix;
  ASSERT_EQ(matrix.rows, 4);
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      EXPECT_DOUBLE_EQ(matrix.at<double>(r, c),
                       result["odom_from_cam"]["matrix"][r][c].get<double>());
    }
  }
}

TEST_F(OdomcalCli, AcceptsTumOdometryAndTwoSegments) {
  const SimulatedDrive drive = WriteDrive(RealisticDrive(12));
  WriteTumTrajectory(drive.odometry, Path("odometry.tum"));
  // Split the camera trajectory into two SfM segments with different frames
  // and scales, as two COLMAP sub-models would be.
  Trajectory first = drive.camera, second = drive.camera;
  const size_t half = drive.camera.poses.size() / 2;
  first.poses.resize(half);
  second.poses.erase(second.poses.begin(), second.poses.begin() + half);
  const Rigid3d other_frame(Eigen::Quaterniond(0.6, 0.0, 0.8, 0.0),
                            Eigen::Vector3d(3.0, -1.0, 2.0));
  for (StampedPose& pose : second.poses) {
    pose.world_from_sensor = other_frame * pose.world_from_sensor;
    pose.world_from_sensor.translation *= 2.5;  // scale becomes s / 2.5
  }
  WriteTumTrajectory(first, Path("camera_0.tum"));
  WriteTumTrajectory(second, Path("camera_1.tum"));
  const CommandResult run =
      Run("calibrate --camera_poses " + Path("camera_0.tum") +
          " --camera_poses " + Path("camera_1.tum") + " --odometry " +
          Path("odometry.tum") + " --output " + Path("result.json"));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const json result = json::parse(ReadFile(Path("result.json")));
  ASSERT_EQ(result["metric_scales"].size(), 2u);
  EXPECT_TRUE(result["metric_scale"].is_null());
  EXPECT_NEAR(
      result["metric_scales"][0].get<double>() / drive.metric_scale, 1.0, 0.01);
  EXPECT_NEAR(
      result["metric_scales"][1].get<double>() / (drive.metric_scale / 2.5),
      1.0,
      0.01);
}

TEST_F(OdomcalCli, StraightDrivingReportsUnobservableNotNumbers) {
  DriveSimulatorOptions options = RealisticDrive(13);
  options.straight_only = true;
  options.yaw_rate_bias_radps = 0.0;
  options.wheel_scale_error_left = options.wheel_scale_error_right = 0.0;
  WriteDrive(options);
  const CommandResult run = Run(BasicArguments());
  EXPECT_EQ(run.exit_code, 3) << run.out << run.err;
  const json result = json::parse(ReadFile(Path("result.json")));
  EXPECT_EQ(result["status"], "unobservable");
  EXPECT_TRUE(result["odom_from_cam"].is_null());
  const auto& unobservable = result["unobservable"];
  EXPECT_NE(
      std::find(unobservable.begin(), unobservable.end(), "translation_x"),
      unobservable.end());
}

TEST_F(OdomcalCli, CamFromWorldPosesAreRefused) {
  const SimulatedDrive drive = WriteDrive(RealisticDrive(14));
  Trajectory inverted = drive.camera;
  for (StampedPose& pose : inverted.poses) {
    pose.world_from_sensor = Inverse(pose.world_from_sensor);
  }
  WriteTumTrajectory(inverted, Path("camera.tum"));
  const CommandResult run = Run(BasicArguments());
  EXPECT_EQ(run.exit_code, 3) << run.out << run.err;
  const json result = json::parse(ReadFile(Path("result.json")));
  EXPECT_EQ(result["status"], "inconsistent_data");
}

TEST_F(OdomcalCli, MalformedOdometryGivesOneLineAndExit2) {
  WriteDrive(RealisticDrive(15));
  std::string text = ReadFile(Path("odometry.csv"));
  const size_t line_start = text.find('\n', text.size() / 2) + 1;
  const size_t comma = text.find(',', line_start);
  text.replace(comma + 1, text.find(',', comma + 1) - comma - 1, "nan");
  std::ofstream(Path("odometry.csv")) << text;
  const CommandResult run = Run(BasicArguments());
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(LineCount(run.err), 1) << run.err;
  EXPECT_NE(run.err.find("odometry.csv:"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(Path("result.json")));
}

TEST_F(OdomcalCli, BadInputsGiveOneLineAndExit2) {
  WriteDrive(RealisticDrive(16));
  std::ofstream(Path("garbage.tum")) << "this is not a trajectory\n";
  std::ofstream(Path("empty.csv")) << "";
  const std::vector<std::string> cases = {
      "calibrate --camera_poses " + Path("missing.tum") + " --odometry " +
          Path("odometry.csv") + " --output " + Path("r.json"),
      "calibrate --camera_poses " + Path("garbage.tum") + " --odometry " +
          Path("odometry.csv") + " --output " + Path("r.json"),
      "calibrate --camera_poses " + Path("camera.tum") + " --odometry " +
          Path("empty.csv") + " --output " + Path("r.json"),
      // Seconds declared as nanoseconds: no camera time inside the odometry.
      BasicArguments() + " --camera_time_unit ns",
      BasicArguments() + " --method nonsense",
      BasicArguments() + " --no_such_flag",
      BasicArguments() + " --cam_rotation_sigma_deg -1",
      "calibrate --camera_poses " + Path("camera.tum") + " --odometry " +
          Path("odometry.csv") + " --output " + Path("no_such_dir/r.json"),
  };
  for (const std::string& arguments : cases) {
    SCOPED_TRACE(arguments);
    const CommandResult run = Run(arguments);
    EXPECT_EQ(run.exit_code, 2) << run.out << run.err;
    EXPECT_EQ(LineCount(run.err), 1) << run.err;
    EXPECT_EQ(run.err.rfind("odomcal", 0), 0u) << run.err;
  }
}

TEST_F(OdomcalCli, NeverOverwritesWithoutFlagAndNeverTouchesInputs) {
  WriteDrive(RealisticDrive(17));
  const std::string camera_before = ReadFile(Path("camera.tum"));
  const std::string odometry_before = ReadFile(Path("odometry.csv"));
  ASSERT_EQ(Run(BasicArguments()).exit_code, 0);
  const std::string result_before = ReadFile(Path("result.json"));
  const CommandResult again = Run(BasicArguments());
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_NE(again.err.find("--overwrite"), std::string::npos) << again.err;
  EXPECT_EQ(ReadFile(Path("result.json")), result_before);
  EXPECT_EQ(Run(BasicArguments() + " --overwrite --method als").exit_code, 0);
  EXPECT_NE(ReadFile(Path("result.json")), result_before);
  EXPECT_EQ(ReadFile(Path("camera.tum")), camera_before);
  EXPECT_EQ(ReadFile(Path("odometry.csv")), odometry_before);
  // No temporary files left behind.
  for (const auto& entry : fs::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().string().find(".tmp."), std::string::npos)
        << entry.path();
  }
}

TEST_F(OdomcalCli, DemoRunsAndMatchesGroundTruth) {
  const CommandResult run =
      Run("demo --simulated --workspace_path " + Path("demo"));
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const json result = json::parse(ReadFile(Path("demo/calibration.json")));
  const json truth = json::parse(ReadFile(Path("demo/ground_truth.json")));
  EXPECT_EQ(result["status"], "success");
  EXPECT_NEAR(result["metric_scale"].get<double>() /
                  truth["metric_scale"].get<double>(),
              1.0,
              0.005);
}

// `render --rig`: one folder of images per camera, their times in one CSV,
// every camera in ground_truth.json and cameras.txt; an overwrite with
// another rig leaves no folder of the first one.
TEST_F(OdomcalCli, RenderRigWritesOneFolderPerCamera) {
  const std::string render =
      "render --preset small --output_path " + Path("rig") + " --num_images 3";
  const CommandResult run =
      Run(render + " --rig surround3 --capped_camera rear");
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  // 0.4 s of images: 0, 0.2, 0.4 s; 0.07, 0.32 s; 0.1, 0.3 s.
  const std::map<std::string, size_t> counts = {
      {"front_left", 3}, {"rear", 2}, {"right", 2}};
  for (const auto& [name, count] : counts) {
    size_t files = 0;
    for (const auto& entry :
         fs::directory_iterator(Path("rig/images/" + name))) {
      EXPECT_EQ(entry.path().extension(), ".png");
      ++files;
    }
    EXPECT_EQ(files, count) << name;
  }
  std::istringstream csv(ReadFile(Path("rig/image_timestamps.csv")));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "image_name,timestamp");
  int rows = 0;
  for (; std::getline(csv, line); ++rows) {
    const std::string name = line.substr(0, line.find(','));
    EXPECT_TRUE(fs::exists(Path("rig/images/" + name))) << line;
  }
  EXPECT_EQ(rows, 7);
  const json truth = json::parse(ReadFile(Path("rig/ground_truth.json")));
  EXPECT_EQ(truth["rig"]["name"], "surround3");
  ASSERT_EQ(truth["cameras"].size(), 3u);
  EXPECT_EQ(truth["cameras"][1]["name"], "rear");
  EXPECT_EQ(truth["cameras"][1]["capped"], true);
  EXPECT_EQ(truth["cameras"][0]["capped"], false);
  EXPECT_EQ(truth["cameras"][1]["rate_hz"], 4.0);
  EXPECT_EQ(truth["cameras"][1]["odom_from_cam"]["translation_m"],
            json::array({-0.25, 0.0, 0.45}));
  EXPECT_EQ(truth["cameras"][1]["num_images"], 2);
  EXPECT_EQ(truth["odom_from_cam"], truth["cameras"][0]["odom_from_cam"]);
  EXPECT_EQ(truth["images"].size(), 3u);
  EXPECT_EQ(
      truth["images"][0]["name"].get<std::string>().rfind("front_left/", 0),
      0u);
  std::istringstream cameras(ReadFile(Path("rig/cameras.txt")));
  int camera_lines = 0;
  while (std::getline(cameras, line)) {
    if (line.empty() || line[0] == '#') continue;
    EXPECT_EQ(line.substr(2), "PINHOLE 320 240 260 260 160 120");
    ++camera_lines;
  }
  EXPECT_EQ(camera_lines, 3);

  const CommandResult stereo = Run(render + " --rig stereo --overwrite");
  ASSERT_EQ(stereo.exit_code, 0) << stereo.out << stereo.err;
  std::set<std::string> folders;
  for (const auto& entry : fs::directory_iterator(Path("rig/images"))) {
    folders.insert(entry.path().filename().string());
  }
  EXPECT_EQ(folders, (std::set<std::string>{"left", "right"}));

  for (const auto& [flags, message] :
       std::vector<std::pair<std::string, std::string>>{
           {"--rig stereo --capped_camera rear",
            "--capped_camera: rig 'stereo' has no camera 'rear' (its "
            "cameras: left, right)"},
           {"--capped_camera left", "--capped_camera caps a camera of a rig"},
           {"--rig stereo --camera_mount 0,0,0,0.2,0,0.4",
            "--camera_mount sets the single camera's mount"}}) {
    const CommandResult refused = Run("render --preset small --output_path " +
                                      Path("refused") + " " + flags);
    EXPECT_EQ(refused.exit_code, 2) << flags;
    EXPECT_EQ(LineCount(refused.err), 1) << refused.err;
    EXPECT_NE(refused.err.find(message), std::string::npos) << refused.err;
    EXPECT_FALSE(fs::exists(Path("refused"))) << flags;
  }
}

}  // namespace
}  // namespace odomcal
