// End-to-end tests of `odomcal colmap` on COLMAP projects generated from a
// simulated drive (until rendered scenes through COLMAP exist): accuracy of
// the extrinsic, scale and metric model, detection of a folded stretch,
// one-line errors, and an input project left byte-identical.

#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/test_support.h"
#include "odomcal/adapters/trajectory_io.h"
#include "odomcal/datasets/simulation/drive_simulator.h"
#include "odomcal/solver/angles.h"
#include "odomcal/tests/test_files.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>

namespace odomcal {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct Project {
  SimulatedDrive drive;
  std::vector<Eigen::Vector3d> points_in_origin;
};

class ColmapCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(::testing::TempDir()) /
           (std::string("colmap_cli_") + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "project" / "sparse");
  }
  void TearDown() override {
    if (std::getenv("ODOMCAL_KEEP_TEST_FILES") == nullptr) fs::remove_all(dir_);
  }

  int Run(const std::string& arguments, std::string* err = nullptr) const {
    const fs::path out = dir_ / "stdout.txt", error = dir_ / "stderr.txt";
    const std::string command = std::string(ODOMCAL_EXECUTABLE) + " " +
                                arguments + " > " + out.string() + " 2> " +
                                error.string();
    const int status = std::system(command.c_str());
    if (err != nullptr) *err = ReadFile(error);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  // A COLMAP project of the drive: sub-model 0 = the first part, sub-model 1
  // = the rest, each in its own similarity frame; images named by index,
  // times in image_timestamps.csv; 200 points seen by nobody in particular.
  Project MakeProject(uint64_t seed, bool fold = false) const {
    DriveSimulatorOptions options;
    options.seed = seed;
    options.duration_s = 80.0;
    // Exact odometry: its frame is then the true origin frame, so the metric
    // model can be checked against the true point positions.
    options.camera_rotation_noise_deg = 0.01;
    options.camera_position_noise = 0.0005;
    Project project;
    project.drive = SimulateDrive(options);
    const SimulatedDrive& drive = project.drive;
    WriteOdometryCsv(drive.odometry, (dir_ / "odometry.csv").string());

    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> uniform(-5.0, 5.0);
    for (int i = 0; i < 200; ++i) {
      project.points_in_origin.emplace_back(
          uniform(rng), uniform(rng), 0.5 * uniform(rng) + 2.0);
    }
    const size_t split = drive.camera.poses.size() * 2 / 3;
    std::ofstream stamps(dir_ / "project" / "image_timestamps.csv");
    stamps << "image_name,timestamp\n";
    for (int part = 0; part < 2; ++part) {
      ColmapModel model;
      model.cameras[1] = MakeColmapCamera(
          1, ColmapCameraModel::kPinhole, 320, 240, {250, 250, 160, 120});
      // Sub-model 1 lives in another frame and scale than the simulator's.
      const Rigid3d frame =
          part == 0 ? Rigid3d()
                    : Rigid3d(Eigen::Quaterniond(0.8, 0.0, 0.6, 0.0),
                              Eigen::Vector3d(1.0, 2.0, 3.0));
      const double extra_scale = part == 0 ? 1.0 : 2.0;
      const size_t begin = part == 0 ? 0 : split - 5;  // 5 shared images
      const size_t end = part == 0 ? split : drive.camera.poses.size();
      for (size_t i = begin; i < end; ++i) {
        Rigid3d world_from_cam =
            frame * drive.camera.poses[i].world_from_sensor;
        world_from_cam.translation *= extra_scale;
        if (fold && part == 0 && i >= 200 && i < 230) {
          // A folded stretch: COLMAP mirrored the path's direction here.
          world_from_cam.translation += Eigen::Vector3d(
              0.0, 0.0, 0.05 * (static_cast<double>(i) - 200.0));
          world_from_cam.rotation =
              world_from_cam.rotation *
              Eigen::Quaterniond(Eigen::AngleAxisd(0.02 * (i - 200.0),
                                                   Eigen::Vector3d::UnitX()));
        }
        ColmapImage image;
        image.image_id =
            static_cast<uint32_t>(1000 - i);  // ids not in name order
        image.camera_id = 1;
        char name[32];
        std::snprintf(name, sizeof(name), "frames/%06zu.png", i);
        image.name = name;
        image.cam_from_world = Inverse(world_from_cam);
        model.images[image.image_id] = image;
        if (part == 0 || i >= split) {
          stamps << image.name << ","
                 << FormatTimestampSeconds(drive.camera.poses[i].stamp_ns)
                 << "\n";
        }
      }
      // Points: origin frame -> the simulator's SfM frame -> this sub-model.
      const Rigid3d& sfm = drive.sfm_from_origin_rotation_translation;
      for (size_t p = 0; p < project.points_in_origin.size(); ++p) {
        ColmapPoint3D point;
        point.point3D_id = static_cast<int64_t>(p + 1);
        const Eigen::Vector3d in_sfm =
            (sfm.rotation * project.points_in_origin[p] + sfm.translation) /
            drive.metric_scale;
        point.xyz = extra_scale * (frame * in_sfm);
        point.error = 0.5;
        model.points3D[point.point3D_id] = point;
      }
      const fs::path folder =
          dir_ / "project" / "sparse" / std::to_string(part);
      fs::create_directories(folder);
      WriteColmapModel(model,
                       folder.string(),
                       part == 0 ? ColmapFormat::kBinary : ColmapFormat::kText);
    }
    return project;
  }

  std::string Arguments(const std::string& output = "out") const {
    return "colmap --model_path " + (dir_ / "project" / "sparse").string() +
           " --odometry " + (dir_ / "odometry.csv").string() +
           " --image_timestamps " +
           (dir_ / "project" / "image_timestamps.csv").string() +
           " --output_path " + (dir_ / output).string() +
           " --fixed_translation_z_m 0.4";
  }

  fs::path dir_;
};

TEST_F(ColmapCli, CalibratesTwoSubModelsAndExportsAMetricModel) {
  const Project project = MakeProject(21);
  const SimulatedDrive& drive = project.drive;
  const auto before = Snapshot(dir_ / "project");
  std::string err;
  // The offset held at 0: the images span exactly the odometry, and an
  // estimate a fraction of a millisecond off would leave out an end image.
  ASSERT_EQ(Run(Arguments() + " --estimate_time_offset off", &err), 0)
      << err << ReadFile(dir_ / "stdout.txt");
  EXPECT_EQ(Snapshot(dir_ / "project"), before) << "the input project changed";

  const json result = json::parse(ReadFile(dir_ / "out" / "calibration.json"));
  EXPECT_EQ(result["status"], "success");
  const auto& q = result["odom_from_cam"]["quaternion_wxyz"];
  const Eigen::Quaterniond rotation(q[0], q[1], q[2], q[3]);
  EXPECT_LT(RotationAngle(rotation.conjugate() * drive.odom_from_cam.rotation) *
                kRadToDeg,
            0.05);
  const auto& t = result["odom_from_cam"]["translation_m"];
  EXPECT_NEAR(t[0].get<double>(), drive.odom_from_cam.translation.x(), 0.003);
  EXPECT_NEAR(t[1].get<double>(), drive.odom_from_cam.translation.y(), 0.003);
  ASSERT_EQ(result["metric_scales"].size(), 2u);
  EXPECT_NEAR(result["metric_scales"][0].get<double>() / drive.metric_scale,
              1.0,
              0.005);
  EXPECT_NEAR(
      result["metric_scales"][1].get<double>() / (drive.metric_scale / 2.0),
      1.0,
      0.005);
  EXPECT_TRUE(result["colmap"]["inconsistent_stretches"].empty());

  // The metric model: points back at their metric positions in the
  // odometry's origin frame; readable as a COLMAP model.
  for (const std::string part : {"0", "1"}) {
    const ColmapModel metric =
        ReadColmapModel((dir_ / "out" / "sparse_metric" / part).string());
    double worst = 0.0;
    for (const auto& [id, point] : metric.points3D) {
      worst = std::max(worst,
                       (point.xyz - project.points_in_origin[id - 1]).norm());
    }
    // Scale and alignment errors of a few mm over points up to 7 m away.
    EXPECT_LT(worst, 0.05) << "sub-model " << part;
  }
  const Trajectory cameras = ReadTumTrajectory(
      (dir_ / "out" / "camera_in_odom.tum").string(), TimeUnit::kSeconds);
  EXPECT_EQ(cameras.poses.size(), drive.camera.poses.size());
  EXPECT_TRUE(fs::exists(dir_ / "out" / "report.html"));
}

TEST_F(ColmapCli, AFoldedStretchIsDetectedAndLeftOut) {
  const Project project = MakeProject(22, /*fold=*/true);
  std::string err;
  ASSERT_EQ(Run(Arguments(), &err), 0) << err << ReadFile(dir_ / "stdout.txt");
  const json result = json::parse(ReadFile(dir_ / "out" / "calibration.json"));
  const auto& stretches = result["colmap"]["inconsistent_stretches"];
  ASSERT_FALSE(stretches.empty()) << result["warnings"];
  bool rejected = false;
  for (const auto& stretch : stretches)
    rejected |= stretch["verdict"] == "rejected";
  EXPECT_TRUE(rejected) << stretches;
  const auto& q = result["odom_from_cam"]["quaternion_wxyz"];
  const Eigen::Quaterniond rotation(q[0], q[1], q[2], q[3]);
  EXPECT_LT(RotationAngle(rotation.conjugate() *
                          project.drive.odom_from_cam.rotation) *
                kRadToDeg,
            0.05);
  EXPECT_NE(ReadFile(dir_ / "stdout.txt").find("contradicts the odometry"),
            std::string::npos);
}

TEST_F(ColmapCli, BadInputsGiveOneLineAndExit2) {
  MakeProject(23);
  fs::create_directories(dir_ / "empty_sparse");
  std::ofstream(dir_ / "broken.db") << "not a database";
  const std::string odometry =
      " --odometry " + (dir_ / "odometry.csv").string();
  const std::string stamps =
      " --image_timestamps " +
      (dir_ / "project" / "image_timestamps.csv").string();
  const std::vector<std::string> cases = {
      "colmap --model_path " + (dir_ / "missing").string() + odometry + stamps +
          " --output_path " + (dir_ / "o1").string(),
      "colmap --model_path " + (dir_ / "empty_sparse").string() + odometry +
          stamps + " --output_path " + (dir_ / "o2").string(),
      Arguments("o3") + " --database_path " + (dir_ / "broken.db").string(),
      // Images outside the odometry span: a clock offset of a day.
      Arguments("o4") + " --camera_time_offset_s 86400",
      // Output inside the input project.
      "colmap --model_path " + (dir_ / "project" / "sparse").string() +
          odometry + stamps + " --output_path " +
          (dir_ / "project" / "sparse" / "out").string(),
  };
  const auto before = Snapshot(dir_ / "project");
  for (const std::string& arguments : cases) {
    SCOPED_TRACE(arguments);
    std::string err;
    EXPECT_EQ(Run(arguments, &err), 2);
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  }
  EXPECT_EQ(Snapshot(dir_ / "project"), before);
}

}  // namespace
}  // namespace odomcal
