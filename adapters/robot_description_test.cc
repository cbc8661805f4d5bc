// The robot formats read back as a robot would read them: the URDF through
// Debian's check_urdf (liburdfdom-tools) and its origins composed, the tf
// commands and the Autoware YAML parsed, each giving odom_from_cam again.
#include "odomcal/adapters/robot_description.h"

#include "odomcal/solver/angles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace odomcal {
namespace {

Rigid3d FromRpy(double roll,
                double pitch,
                double yaw,
                const Eigen::Vector3d& xyz) {
  const Eigen::Quaterniond q =
      Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
      Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
      Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
  return Rigid3d(q, xyz);
}

// Mounts to test: a forward camera pitched 20 deg down and turned 3 deg
// left, one at an arbitrary attitude, one looking straight down (its body
// frame's pitch is +90 deg: gimbal lock of roll-pitch-yaw).
std::vector<Rigid3d> Mounts() {
  const Rigid3d forward_optical = FromRpy(-kPi / 2, 0.0, -kPi / 2, {0, 0, 0});
  return {
      FromRpy(0.0, 20.0 * kPi / 180, 3.0 * kPi / 180, {0.31, -0.042, 0.5}) *
          forward_optical,
      FromRpy(0.7, -1.1, 2.9, {-0.2, 0.13, 0.0}),
      FromRpy(0.0, kPi / 2, 0.0, {0.1, 0.0, 0.8}) * forward_optical,
  };
}

void ExpectSameTransform(const Rigid3d& a, const Rigid3d& b, double tol) {
  EXPECT_LT((a.translation - b.translation).norm(), tol);
  EXPECT_LT(RotationAngle(a.rotation.conjugate() * b.rotation), tol);
}

std::vector<double> Numbers(const std::string& text) {
  std::vector<double> values;
  std::istringstream in(text);
  std::string token;
  while (in >> token) values.push_back(std::stod(token));
  return values;
}

// Every joint's origin of a URDF fragment, in order.
std::vector<Rigid3d> UrdfOrigins(const std::string& urdf) {
  std::vector<Rigid3d> origins;
  const std::regex origin("<origin xyz=\"([^\"]*)\" rpy=\"([^\"]*)\"/>");
  for (auto it = std::sregex_iterator(urdf.begin(), urdf.end(), origin);
       it != std::sregex_iterator();
       ++it) {
    const std::vector<double> xyz = Numbers((*it)[1]);
    const std::vector<double> rpy = Numbers((*it)[2]);
    EXPECT_EQ(xyz.size(), 3u);
    EXPECT_EQ(rpy.size(), 3u);
    origins.push_back(
        FromRpy(rpy[0], rpy[1], rpy[2], {xyz[0], xyz[1], xyz[2]}));
  }
  return origins;
}

Rigid3d Compose(const std::vector<Rigid3d>& chain) {
  Rigid3d result;
  for (const Rigid3d& link : chain) result = result * link;
  return result;
}

std::string TempPath(const std::string& name) {
  return (std::filesystem::path(testing::TempDir()) / name).string();
}

// check_urdf's exit status and output on a robot holding the fragment.
int CheckUrdf(const std::string& robot_xml, std::string* output) {
  const std::string path = TempPath("odomcal_robot.urdf");
  std::ofstream(path) << robot_xml;
  const std::string log = TempPath("odomcal_check_urdf.log");
  const int status =
      std::system(("check_urdf " + path + " > " + log + " 2>&1").c_str());
  std::ifstream in(log);
  *output = std::string(std::istreambuf_iterator<char>(in), {});
  return status;
}

TEST(RobotDescription, UrdfFragmentLoadsAndComposesBackToTheExtrinsic) {
  ASSERT_EQ(std::system("command -v check_urdf > /dev/null"), 0)
      << "check_urdf missing: apt-get install liburdfdom-tools "
         "(scripts/install_deps.sh)";
  for (const bool body_frame : {false, true}) {
    for (const Rigid3d& odom_from_cam : Mounts()) {
      RobotFrameNames frames;
      if (body_frame) frames.camera_body_frame = "camera_link";
      const std::string fragment = UrdfFragment(
          MakeRobotDescription(odom_from_cam, frames, true, std::nullopt));
      std::string output;
      EXPECT_EQ(CheckUrdf("<?xml version=\"1.0\"?>\n<robot name=\"r\">\n"
                          "<link name=\"base_link\"/>\n" +
                              fragment + "</robot>\n",
                          &output),
                0)
          << fragment << output;
      EXPECT_NE(output.find("root Link: base_link"), std::string::npos)
          << output;
      const std::vector<Rigid3d> origins = UrdfOrigins(fragment);
      ASSERT_EQ(origins.size(), body_frame ? 2u : 1u) << fragment;
      ExpectSameTransform(Compose(origins), odom_from_cam, 1e-9);
      if (body_frame) {
        ExpectSameTransform(origins[1], BodyFromOpticalRotation(), 1e-9);
      }
    }
  }
}

TEST(RobotDescription, TheHeldHeightIsNamed) {
  const Rigid3d mount = Mounts()[0];
  const RobotDescription held =
      MakeRobotDescription(mount, RobotFrameNames(), true, std::nullopt);
  for (const std::string& text : {UrdfFragment(held),
                                  Ros2StaticTransformCommands(held),
                                  Ros1StaticTransformCommands(held),
                                  AutowareSensorsCalibrationYaml(held)}) {
    EXPECT_NE(text.find("the camera height (z = 0.5 m above base_link) is "
                        "the value given with --fixed_translation_z_m, not "
                        "measured"),
              std::string::npos)
        << text;
  }
  // Each file's first line names it as odomcal's (IsOdomcalResultFile).
  DiffDriveCorrections corrections;
  const RobotDescription with_wheels =
      MakeRobotDescription(mount, RobotFrameNames(), true, corrections);
  EXPECT_EQ(UrdfFragment(with_wheels).rfind("<!-- odomcal robot output: ", 0),
            0u);
  for (const std::string& text : {Ros2StaticTransformCommands(with_wheels),
                                  Ros1StaticTransformCommands(with_wheels),
                                  AutowareSensorsCalibrationYaml(with_wheels),
                                  DiffDriveControllerYaml(with_wheels)}) {
    EXPECT_EQ(text.rfind("# odomcal robot output: ", 0), 0u) << text;
  }
  const RobotDescription estimated =
      MakeRobotDescription(mount, RobotFrameNames(), false, std::nullopt);
  EXPECT_EQ(UrdfFragment(estimated).find("height"), std::string::npos);
}

// Values after "--name" in a ROS 2 command line.
std::map<std::string, std::string> Ros2Arguments(const std::string& line) {
  std::map<std::string, std::string> arguments;
  std::istringstream in(line);
  std::string token;
  while (in >> token) {
    if (token.rfind("--", 0) == 0) in >> arguments[token.substr(2)];
  }
  return arguments;
}

std::vector<std::string> CommandLines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] != '#') lines.push_back(line);
  }
  return lines;
}

Rigid3d FromXyzQuaternion(const std::vector<double>& v) {
  return Rigid3d(Eigen::Quaterniond(v[6], v[3], v[4], v[5]),
                 Eigen::Vector3d(v[0], v[1], v[2]));
}

TEST(RobotDescription, TfCommandsParseBackToTheExtrinsic) {
  for (const bool body_frame : {false, true}) {
    for (const Rigid3d& odom_from_cam : Mounts()) {
      RobotFrameNames frames;
      frames.base_frame = "base_footprint";
      frames.camera_frame = "front/camera_optical";
      if (body_frame) frames.camera_body_frame = "front/camera";
      const RobotDescription robot =
          MakeRobotDescription(odom_from_cam, frames, true, std::nullopt);

      std::vector<Rigid3d> ros2_chain;
      std::vector<std::string> ros2_frames;
      for (const std::string& line :
           CommandLines(Ros2StaticTransformCommands(robot))) {
        ASSERT_EQ(line.rfind("ros2 run tf2_ros static_transform_publisher ", 0),
                  0u)
            << line;
        std::map<std::string, std::string> a = Ros2Arguments(line);
        std::vector<double> values;
        for (const char* name : {"x", "y", "z", "qx", "qy", "qz", "qw"}) {
          ASSERT_EQ(a.count(name), 1u) << name << " in " << line;
          values.push_back(std::stod(a[name]));
        }
        ros2_chain.push_back(FromXyzQuaternion(values));
        ros2_frames.push_back(a["frame-id"] + ">" + a["child-frame-id"]);
      }
      ExpectSameTransform(Compose(ros2_chain), odom_from_cam, 1e-9);

      std::vector<Rigid3d> ros1_chain;
      std::vector<std::string> ros1_frames;
      for (const std::string& line :
           CommandLines(Ros1StaticTransformCommands(robot))) {
        std::istringstream in(line);
        std::string rosrun, package, node, parent, child, period;
        in >> rosrun >> package >> node;
        EXPECT_EQ(rosrun + " " + package + " " + node,
                  "rosrun tf static_transform_publisher");
        std::vector<double> values(7);
        for (double& value : values) in >> value;
        in >> parent >> child >> period;
        EXPECT_EQ(period, "100");
        ros1_chain.push_back(FromXyzQuaternion(values));
        ros1_frames.push_back(parent + ">" + child);
      }
      ExpectSameTransform(Compose(ros1_chain), odom_from_cam, 1e-9);

      const std::vector<std::string> expected_frames =
          body_frame
              ? std::vector<std::string>{"base_footprint>front/camera",
                                         "front/camera>front/"
                                         "camera_optical"}
              : std::vector<std::string>{"base_footprint>front/camera_optical"};
      EXPECT_EQ(ros2_frames, expected_frames);
      EXPECT_EQ(ros1_frames, expected_frames);
    }
  }
}

TEST(RobotDescription, AutowareYamlParsesBackToTheExtrinsic) {
  for (const Rigid3d& odom_from_cam : Mounts()) {
    const std::string yaml =
        AutowareSensorsCalibrationYaml(MakeRobotDescription(
            odom_from_cam, RobotFrameNames(), true, std::nullopt));
    std::map<std::string, double> values;
    std::istringstream in(yaml);
    std::string line;
    std::vector<std::string> keys;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#') continue;
      const size_t colon = line.find(':');
      ASSERT_NE(colon, std::string::npos) << line;
      const std::string key = line.substr(0, colon);
      if (colon + 1 == line.size()) {
        keys.push_back(key);
      } else {
        values[key.substr(key.find_first_not_of(' '))] =
            std::stod(line.substr(colon + 1));
      }
    }
    EXPECT_EQ(
        keys,
        (std::vector<std::string>{"base_link", "  camera_optical_frame"}));
    ASSERT_EQ(values.size(), 6u) << yaml;
    ExpectSameTransform(FromRpy(values["roll"],
                                values["pitch"],
                                values["yaw"],
                                {values["x"], values["y"], values["z"]}),
                        odom_from_cam,
                        1e-9);
  }
}

TEST(RobotFrameNames, CheckNamesTheFlag) {
  const auto message = [](const RobotFrameNames& frames) -> std::string {
    try {
      frames.Check();
    } catch (const std::invalid_argument& error) {
      return error.what();
    }
    return "";
  };
  RobotFrameNames frames;
  EXPECT_EQ(message(frames), "");
  frames.camera_body_frame = "camera_link";
  EXPECT_EQ(message(frames), "");
  frames.base_frame = "base link";
  EXPECT_EQ(message(frames),
            "--base_frame \"base link\" is not a frame name: use letters, "
            "digits and _ - . /");
  frames.base_frame = "base_link";
  frames.camera_frame = "";
  EXPECT_EQ(message(frames),
            "--camera_frame must be 1 to 200 characters, got \"\"");
  frames.camera_frame = "camera_link";
  EXPECT_EQ(message(frames),
            "--base_frame, --camera_frame and --camera_body_frame must name "
            "different frames, got \"base_link\", \"camera_link\" and "
            "\"camera_link\"");
  frames.camera_frame = "cam\"<x>";
  EXPECT_NE(message(frames).find("--camera_frame"), std::string::npos);
}

TEST(DiffDriveCorrections, InvertTheIntrinsicsModel) {
  // Wheels kl = 1.02, kr = 0.99 of nominal, track 1.03 of nominal 0.4 m:
  // yaw_scale = ((kl + kr) / 2) / k_track, yaw_per_metre = (kr - kl) /
  // (k_track b). The common factor 1.005 is not observable: the corrections
  // are the truth over it.
  const double kl = 1.02, kr = 0.99, kt = 1.03, b = 0.4;
  OdometryIntrinsics intrinsics;
  intrinsics.yaw_scale = 0.5 * (kl + kr) / kt;
  intrinsics.yaw_per_metre_rad = (kr - kl) / (kt * b);
  intrinsics.wheel_track_m = b;
  const auto corrections = DiffDriveCorrectionsFrom(
      intrinsics, {true, true, false}, {0.001, 0.002, 0.0});
  ASSERT_TRUE(corrections.has_value());
  const double mean = 0.5 * (kl + kr);
  EXPECT_NEAR(corrections->wheel_separation_multiplier, kt / mean, 1e-12);
  EXPECT_NEAR(corrections->left_wheel_radius_multiplier, kl / mean, 1e-12);
  EXPECT_NEAR(corrections->right_wheel_radius_multiplier, kr / mean, 1e-12);
  EXPECT_TRUE(corrections->radius_difference_estimated);
  EXPECT_GT(corrections->wheel_radius_multiplier_stddev, 0.0);
  EXPECT_NEAR(corrections->wheel_separation_multiplier_stddev,
              0.001 / (intrinsics.yaw_scale * intrinsics.yaw_scale),
              1e-15);

  EXPECT_FALSE(DiffDriveCorrectionsFrom(intrinsics, {false, true, false}, {})
                   .has_value());
  intrinsics.wheel_track_m = 0.0;
  EXPECT_FALSE(DiffDriveCorrectionsFrom(intrinsics, {true, true, false}, {})
                   .has_value());
}

TEST(DiffDriveCorrections, ControllerYamlNamesWhatItHolds) {
  DiffDriveCorrections corrections;
  corrections.wheel_separation_multiplier = 1.03;
  corrections.yaw_rate_bias_rad_s = 0.002;
  const std::string yaml = DiffDriveControllerYaml(
      MakeRobotDescription(Mounts()[0], RobotFrameNames(), true, corrections));
  EXPECT_NE(yaml.find("diff_drive_controller:\n  ros__parameters:\n"
                      "    wheel_separation_multiplier: 1.03\n"
                      "    left_wheel_radius_multiplier: 1\n"
                      "    right_wheel_radius_multiplier: 1\n"),
            std::string::npos)
      << yaml;
  EXPECT_NE(yaml.find("common distance scale is held at 1"), std::string::npos);
  EXPECT_NE(yaml.find("radius difference was not estimated"),
            std::string::npos);
  EXPECT_NE(yaml.find("heading drift of 0.002 rad/s"), std::string::npos);
  EXPECT_EQ(DiffDriveControllerYaml(MakeRobotDescription(
                Mounts()[0], RobotFrameNames(), true, std::nullopt)),
            "");
}

}  // namespace
}  // namespace odomcal
