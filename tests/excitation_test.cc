// Weak excitation and honest exits (docs/robustness.md, "Weak excitation and
// honest exits"): `odomcal run` refuses a drive whose odometry cannot
// determine the calibration before any COLMAP stage; a COLMAP failure exits
// 4; a refused calibration is printed as not a calibration; outputs without
// content are neither written nor listed.
//
// COLMAP is a fake `colmap` script on PATH that records every call.

#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/test_support.h"
#include "odomcal/adapters/timestamp.h"
#include "odomcal/adapters/trajectory_io.h"
#include "odomcal/datasets/simulation/drive_simulator.h"
#include "odomcal/datasets/simulation/model_noise.h"
#include "odomcal/solver/angles.h"
#include "odomcal/tests/odomcal_process.h"
#include "odomcal/tests/scratch_folder_test.h"
#include "odomcal/tests/test_files.h"

#include <sys/stat.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sqlite3.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

namespace odomcal {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr int kImages = 50;

std::string ImageName(int index) {
  char name[32];
  std::snprintf(name, sizeof(name), "%06d.png", index);
  return name;
}

class Excitation : public ScratchFolderTest {
 protected:
  Excitation() : ScratchFolderTest("odomcal_excitation_") {}

  // A 60 s simulated drive (straight only, or with turns both ways):
  // odometry.csv, camera.tum, and images/ with kImages files at the camera
  // times every 1 s, image_timestamps.csv.
  SimulatedDrive WriteDrive(bool straight) const {
    DriveSimulatorOptions options;
    options.seed = 3;
    options.straight_only = straight;
    const SimulatedDrive drive = SimulateDrive(options);
    WriteOdometryCsv(drive.odometry, Path("odometry.csv"));
    WriteTumTrajectory(drive.camera, Path("camera.tum"));
    fs::create_directories(dir_ / "images");
    std::string stamps;
    for (int i = 0; i < kImages; ++i) {
      WriteFile(dir_ / "images" / ImageName(i), "x");
      stamps +=
          ImageName(i) + "," +
          FormatTimestampSeconds(drive.camera.poses[10 * i + 10].stamp_ns) +
          "\n";
    }
    WriteFile(Path("image_timestamps.csv"), stamps);
    return drive;
  }

  // bin/colmap: records each call's arguments in colmap_calls.txt, prints
  // COLMAP 3.8's banner for `help`, and runs `body` (sh) for a subcommand.
  std::string WriteFakeColmap(const std::string& body) const {
    fs::create_directories(dir_ / "bin");
    const fs::path script = dir_ / "bin" / "colmap";
    WriteFile(script,
              "#!/bin/sh\n"
              "echo \"$*\" >> " +
                  Path("colmap_calls.txt") +
                  "\n"
                  "if [ \"$1\" = help ]; then\n"
                  "  echo 'COLMAP 3.8 -- Structure-from-Motion and Multi-View "
                  "Stereo'\n"
                  "  exit 0\n"
                  "fi\n" +
                  body);
    ::chmod(script.c_str(), 0755);
    return "PATH=" + (dir_ / "bin").string() + ":/usr/bin:/bin";
  }

  // prepared.db: COLMAP 3.8's cameras and images tables holding every image
  // of images/, as feature_extractor would leave them.
  std::string WritePreparedDatabase() const {
    const std::string path = Path("prepared.db");
    sqlite3* db = nullptr;
    EXPECT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    std::string sql =
        "CREATE TABLE images (image_id INTEGER PRIMARY KEY AUTOINCREMENT NOT "
        "NULL, "
        "name TEXT NOT NULL UNIQUE, camera_id INTEGER NOT NULL, prior_qw REAL, "
        "prior_qx REAL, prior_qy REAL, prior_qz REAL, prior_tx REAL, prior_ty "
        "REAL, "
        "prior_tz REAL);"
        "CREATE TABLE cameras (camera_id INTEGER PRIMARY KEY AUTOINCREMENT NOT "
        "NULL, "
        "model INTEGER NOT NULL, width INTEGER NOT NULL, height INTEGER NOT "
        "NULL, "
        "params BLOB, prior_focal_length INTEGER NOT NULL);"
        "INSERT INTO cameras VALUES (1, 1, 320, 240, "
        "X'0000000000407040000000000040704000000000000064400000000000005e40', "
        "1);";
    for (int i = 0; i < kImages; ++i) {
      sql += "INSERT INTO images (image_id, name, camera_id) VALUES (" +
             std::to_string(i + 1) + ", '" + ImageName(i) + "', 1);";
    }
    EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr),
              SQLITE_OK)
        << sqlite3_errmsg(db);
    sqlite3_close(db);
    return path;
  }

  // model/: the drive's camera poses of the first `num_images` images (all
  // by default), as the mapper would register them (no points).
  std::string WriteModel(const SimulatedDrive& drive,
                         int num_images = kImages) const {
    ColmapModel model;
    model.cameras[1] = MakeColmapCamera(
        1, ColmapCameraModel::kPinhole, 320, 240, {260, 260, 160, 120});
    for (int i = 0; i < num_images; ++i) {
      ColmapImage image;
      image.image_id = static_cast<uint32_t>(i + 1);
      image.camera_id = 1;
      image.name = ImageName(i);
      image.cam_from_world =
          Inverse(drive.camera.poses[10 * i + 10].world_from_sensor);
      model.images[image.image_id] = image;
    }
    fs::create_directories(dir_ / "model");
    WriteColmapModel(model, Path("model"), ColmapFormat::kBinary);
    return Path("model");
  }

  // A fake COLMAP whose feature extractor leaves prepared.db and whose
  // mapper writes `model` as its sub-model 0; the PATH to run it with.
  std::string WriteMappingColmap(const std::string& model) const {
    return WriteFakeColmap(
        "if [ \"$1\" = feature_extractor ]; then cp " +
        WritePreparedDatabase() +
        " \"$3\"; fi\n"
        "if [ \"$1\" = mapper ]; then\n"
        "  while [ $# -gt 0 ]; do [ \"$1\" = --output_path ] && out=\"$2\"; "
        "shift; done\n"
        "  mkdir -p \"$out/0\" && cp " +
        model +
        "/* \"$out/0/\"\n"
        "fi\n"
        "exit 0\n");
  }

  std::vector<std::string> RunCommand(
      const std::vector<std::string>& extra = {}) const {
    std::vector<std::string> arguments = {"run",
                                          "--image_path",
                                          Path("images"),
                                          "--odometry",
                                          Path("odometry.csv"),
                                          "--image_timestamps",
                                          Path("image_timestamps.csv"),
                                          "--camera_model",
                                          "PINHOLE",
                                          "--camera_params",
                                          "260,260,160,120",
                                          "--matcher",
                                          "sequential",
                                          "--workspace_path",
                                          Path("ws"),
                                          "--num_threads",
                                          "1"};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    return arguments;
  }
};

constexpr char kStraightMessage[] =
    "no motion pair rotates by more than 2 deg (straight driving or no "
    "motion): the rotation "
    "and the x/y translation of the extrinsic cannot be determined; drive "
    "turns in both "
    "directions";

// The user's straight drive: refused within seconds from the odometry, exit
// 3, calibration.json with the solver's status, and COLMAP never called.
TEST_F(Excitation, StraightDriveIsRefusedBeforeColmap) {
  WriteDrive(/*straight=*/true);
  const std::string path = WriteFakeColmap("exit 1\n");
  const auto start = std::chrono::steady_clock::now();
  const CommandResult run = RunOdomcal(RunCommand(), {{path}});
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  EXPECT_EQ(run.exit_code, 3) << run.out << run.err;
  EXPECT_LT(seconds, 10.0);
  EXPECT_EQ(run.err, "");
  EXPECT_FALSE(fs::exists(Path("colmap_calls.txt")))
      << ReadFile(Path("colmap_calls.txt"));
  for (const char* entry : {"database.db",
                            "commands.txt",
                            "logs",
                            "stages",
                            "sparse",
                            "sparse_metric",
                            "camera_in_odom.tum",
                            "report.html",
                            "calibration.yaml"}) {
    EXPECT_FALSE(fs::exists(dir_ / "ws" / entry)) << entry;
  }
  EXPECT_NE(
      run.out.find(
          "excitation (odometry at the " + std::to_string(kImages) +
          " image times): " + std::to_string(kImages - 1) +
          " motion pairs, 0 left and 0 right turns above 2 deg: the "
          "calibration cannot be determined (unobservable); no COLMAP stage "
          "is run (--force runs them anyway)\n"),
      std::string::npos)
      << run.out;
  const std::string message =
      std::string(kStraightMessage) +
      " (seen in the odometry at the image times, before COLMAP; "
      "--force runs it anyway)";
  EXPECT_NE(run.out.find("wrote " + Path("ws/calibration.json") +
                         " (the status only)\n"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("odomcal run: not a calibration (unobservable): " +
                         message + "\n"),
            std::string::npos)
      << run.out;
  EXPECT_NE(
      run.out.find(
          "  no estimate; undetermined: rotation translation_x translation_y "
          "translation_z\n"),
      std::string::npos)
      << run.out;
  EXPECT_EQ(run.out.find("report:"), std::string::npos) << run.out;
  const json result = json::parse(ReadFile(Path("ws/calibration.json")));
  EXPECT_EQ(result["status"], "unobservable");
  EXPECT_EQ(result["message"], message);
  EXPECT_EQ(
      result["unobservable"],
      json::array(
          {"rotation", "translation_x", "translation_y", "translation_z"}));
  EXPECT_TRUE(result["odom_from_cam"].is_null());
  EXPECT_TRUE(result["colmap"]["mapper_attempts"].empty());
}

// A car's drive whose only turn goes right (52 m at 10 m/s, one 98 deg
// turn at 0.6 rad/s with 0.5 s ramps, 10 Hz images, camera 1.65 m up), its
// odometry and reconstruction as noisy as the default noise model says:
// `calibrate` refuses it, and `run` refuses it before COLMAP with the same
// reason (a check that estimated the noise from its exact poses would find
// the noise at its floor and pass it).
TEST_F(Excitation, OneDirectionRoadDriveIsRefusedBeforeColmapAsCalibrateIs) {
  Trajectory truth;
  truth.planar = true;
  std::vector<int64_t> image_stamps;
  const int64_t start_ns = 1700000000000000000;
  double x = 0.0, y = 0.0, yaw = 0.0;
  for (int k = 0; k <= 260; ++k) {  // 50 Hz, 5.2 s
    const int64_t stamp = start_ns + k * 20000000LL;
    truth.poses.push_back(
        {stamp, Rigid3d(YawRotation(yaw), Eigen::Vector3d(x, y, 0.0))});
    if (k % 5 == 0) image_stamps.push_back(stamp);
    const double t = 0.02 * k, peak = 0.6, ramp = 0.5, begin = 0.925;
    const double end = begin + 98.0 * kDegToRad / peak + ramp;
    const double rate = t < begin || t >= end ? 0.0
                        : t < begin + ramp    ? peak * (t - begin) / ramp
                        : t >= end - ramp     ? peak * (end - t) / ramp
                                              : peak;
    const double mid_yaw = yaw - 0.5 * rate * 0.02;
    x += 10.0 * 0.02 * std::cos(mid_yaw);
    y += 10.0 * 0.02 * std::sin(mid_yaw);
    yaw -= rate * 0.02;
  }
  const Rigid3d odom_from_cam(Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5),
                              Eigen::Vector3d(1.5, 0.0, 1.65));
  WriteOdometryCsv(
      WithModelOdometryNoise(truth, image_stamps, NoiseModel(), 1.0, 5),
      Path("odometry.csv"));
  WriteTumTrajectory(ModelNoisyReconstruction(truth,
                                              image_stamps,
                                              image_stamps,
                                              odom_from_cam,
                                              0.37,
                                              NoiseModel(),
                                              1.0,
                                              6),
                     Path("camera.tum"));
  fs::create_directories(dir_ / "images");
  std::string stamps;
  for (size_t i = 0; i < image_stamps.size(); ++i) {
    const std::string name = ImageName(static_cast<int>(i));
    WriteFile(dir_ / "images" / name, "x");
    stamps += name + "," + FormatTimestampSeconds(image_stamps[i]) + "\n";
  }
  WriteFile(Path("image_timestamps.csv"), stamps);

  const CommandResult calibrate = RunOdomcal({"calibrate",
                                              "--camera_poses",
                                              Path("camera.tum"),
                                              "--odometry",
                                              Path("odometry.csv"),
                                              "--output",
                                              Path("result.json")});
  EXPECT_EQ(calibrate.exit_code, 3) << calibrate.out << calibrate.err;
  const json calibrated = json::parse(ReadFile(Path("result.json")));
  EXPECT_EQ(calibrated["status"], "unobservable");
  const std::string message = calibrated["message"];
  EXPECT_NE(message.find("translation_y"), std::string::npos) << message;

  const std::string path = WriteFakeColmap("exit 1\n");
  const CommandResult run = RunOdomcal(RunCommand(), {{path}});
  EXPECT_EQ(run.exit_code, 3) << run.out << run.err;
  EXPECT_FALSE(fs::exists(Path("colmap_calls.txt")))
      << ReadFile(Path("colmap_calls.txt"));
  EXPECT_NE(run.out.find("image times): 52 motion pairs, 0 left and 28 right "
                         "turns above 2 deg: the calibration cannot be "
                         "determined (unobservable); no COLMAP stage is run"),
            std::string::npos)
      << run.out;
  const json refused = json::parse(ReadFile(Path("ws/calibration.json")));
  EXPECT_EQ(refused["status"], "unobservable");
  EXPECT_EQ(refused["message"],
            message +
                " (seen in the odometry at the image times, before COLMAP; "
                "--force runs it anyway)");
  EXPECT_EQ(refused["unobservable"], calibrated["unobservable"]);
}

// --force: COLMAP runs anyway (here it fails at once: exit 4).
TEST_F(Excitation, ForceRunsColmapAnyway) {
  WriteDrive(/*straight=*/true);
  const std::string path =
      WriteFakeColmap("echo 'no GPU, no luck' >&2\nexit 1\n");
  const CommandResult run = RunOdomcal(RunCommand({"--force"}), {{path}});
  EXPECT_NE(run.out.find(
                "the calibration cannot be determined (unobservable); running "
                "COLMAP anyway (--force)\n"),
            std::string::npos)
      << run.out;
  EXPECT_EQ(
      ReadFile(Path("colmap_calls.txt")).rfind("help\nfeature_extractor ", 0),
      0u)
      << ReadFile(Path("colmap_calls.txt"));
  EXPECT_EQ(run.exit_code, 4) << run.out << run.err;
}

// A COLMAP failure has its own exit code, 4 (2 is for bad arguments).
TEST_F(Excitation, ColmapFailureExitsFour) {
  WriteDrive(/*straight=*/false);
  const std::string path =
      WriteFakeColmap("echo 'no GPU, no luck' >&2\nexit 1\n");
  const CommandResult run = RunOdomcal(RunCommand(), {{path}});
  EXPECT_EQ(run.exit_code, 4) << run.out << run.err;
  EXPECT_EQ(
      run.err,
      "odomcal run: error: COLMAP feature_extractor failed with exit code 1; "
      "see " +
          Path("ws/logs/feature_extractor.log") +
          " (last line: no GPU, no luck)\n");
  EXPECT_NE(run.out.find("turns above 2 deg: enough to calibrate\n"),
            std::string::npos)
      << run.out;
  // COLMAP missing: exit 4 too.
  const CommandResult missing =
      RunOdomcal(RunCommand(), {{"PATH=" + Path("empty_bin")}});
  EXPECT_EQ(missing.exit_code, 4) << missing.out << missing.err;
  EXPECT_EQ(missing.err,
            "odomcal run: error: COLMAP not found: 'colmap' is not an "
            "executable on PATH "
            "(install Debian's colmap package or pass --colmap_path)\n");
}

// `calibrate` refuses a straight drive: no number is printed.
TEST_F(Excitation, RefusedCalibrationIsPrintedAsNotACalibration) {
  WriteDrive(/*straight=*/true);
  const CommandResult run = RunOdomcal({"calibrate",
                                        "--camera_poses",
                                        Path("camera.tum"),
                                        "--odometry",
                                        Path("odometry.csv"),
                                        "--output",
                                        Path("result.json")});
  EXPECT_EQ(run.exit_code, 3) << run.out << run.err;
  EXPECT_EQ(
      run.out.rfind("odomcal calibrate: not a calibration (unobservable): " +
                        std::string(kStraightMessage) + "\n",
                    0),
      0u)
      << run.out;
  for (const char* number :
       {"odom_from_cam (", "roll", "quaternion", " cm", "m/unit"}) {
    EXPECT_EQ(run.out.find(number), std::string::npos) << number << "\n"
                                                       << run.out;
  }
}

// Circles of one size: the solver has a closed-form estimate but refuses
// it; the summary labels it as not a calibration.
TEST_F(Excitation, PartialEstimateIsLabelledNotACalibration) {
  DriveSimulatorOptions options;
  options.max_yaw_rate_radps = 0.0;
  Trajectory odometry, camera;
  odometry.planar = true;
  const Rigid3d odom_from_cam = options.odom_from_cam;
  double x = 0.0, y = 0.0, yaw = 0.0;
  for (int k = 0; k <= 3000; ++k) {
    const int64_t stamp = options.start_stamp_ns + k * 20000000LL;
    const Rigid3d pose(YawRotation(yaw), Eigen::Vector3d(x, y, 0.0));
    odometry.poses.push_back({stamp, pose});
    if (k % 5 == 0) {
      Rigid3d world_from_cam = pose * odom_from_cam;
      world_from_cam.translation /= 0.37;
      camera.poses.push_back({stamp, world_from_cam});
    }
    const double mid_yaw = yaw + 0.5 * 0.3 * 0.02;
    x += 0.3 * 0.02 * std::cos(mid_yaw);
    y += 0.3 * 0.02 * std::sin(mid_yaw);
    yaw += 0.3 * 0.02;
  }
  WriteOdometryCsv(odometry, Path("odometry.csv"));
  WriteTumTrajectory(camera, Path("camera.tum"));
  const CommandResult run = RunOdomcal({"calibrate",
                                        "--camera_poses",
                                        Path("camera.tum"),
                                        "--odometry",
                                        Path("odometry.csv"),
                                        "--output",
                                        Path("result.json")});
  EXPECT_EQ(run.exit_code, 3) << run.out << run.err;
  EXPECT_EQ(
      run.out.rfind(
          "odomcal calibrate: not a calibration (unobservable): the motion "
          "does not determine: ",
          0),
      0u)
      << run.out;
  EXPECT_NE(
      run.out.find(
          "\n  undetermined: translation_z rotation translation_x "
          "translation_y metric_scale\n  partial estimate, NOT a calibration "
          "(do not use it; odom_from_cam, x_in_odom = odom_from_cam * "
          "x_in_cam):\n"),
      std::string::npos)
      << run.out;
  EXPECT_EQ(run.out.find("\n  odom_from_cam ("), std::string::npos) << run.out;
}

// `colmap` on a reconstruction of the straight drive: no extrinsic, so no
// metric model and no camera trajectory in metres; neither is written nor
// listed (and an earlier run's are removed).
TEST_F(Excitation, ColmapListsOnlyOutputsWithContent) {
  const SimulatedDrive drive = WriteDrive(/*straight=*/true);
  const std::string model = WriteModel(drive);
  fs::create_directories(dir_ / "out" / "sparse_metric" / "0");
  WriteFile(Path("out/camera_in_odom.tum"), "# an earlier run's\n");
  WriteFile(Path("out/.odomcal_outputs"),
            "sparse_metric\ncamera_in_odom.tum\n");
  const CommandResult run = RunOdomcal({"colmap",
                                        "--model_path",
                                        model,
                                        "--odometry",
                                        Path("odometry.csv"),
                                        "--image_timestamps",
                                        Path("image_timestamps.csv"),
                                        "--output_path",
                                        Path("out"),
                                        "--overwrite"});
  EXPECT_EQ(run.exit_code, 3) << run.out << run.err;
  EXPECT_NE(
      run.out.find("  wrote " + Path("out") +
                   "/{calibration.json, calibration.yaml, report.html}\n"),
      std::string::npos)
      << run.out;
  EXPECT_FALSE(fs::exists(dir_ / "out" / "sparse_metric"));
  EXPECT_FALSE(fs::exists(dir_ / "out" / "camera_in_odom.tum"));
}

// A drive that turns enough, of which COLMAP's model holds three images:
// the refusal says that the reconstruction, not the drive, lacks the motion
// (its own advice, to drive turns, would send the user to the wrong place).
TEST_F(Excitation, AModelThatLostTheTurnsIsBlamedNotTheDrive) {
  const SimulatedDrive drive = WriteDrive(/*straight=*/false);
  const std::string model = WriteModel(drive, 3);
  const std::string path = WriteMappingColmap(model);
  const CommandResult run = RunOdomcal(RunCommand(), {{path}});
  EXPECT_EQ(run.exit_code, 3) << run.out << run.err;
  EXPECT_NE(run.out.find("turns above 2 deg: enough to calibrate\n"),
            std::string::npos)
      << run.out;
  const std::string lost =
      "the motion was lost in the reconstruction, not in the drive";
  EXPECT_NE(run.out.find("odomcal run: not a calibration (not_enough_motion)"),
            std::string::npos)
      << run.out;
  const json result = json::parse(ReadFile(Path("ws/calibration.json")));
  EXPECT_NE(result["message"].get<std::string>().find(lost), std::string::npos)
      << result["message"];
  bool warned = false;
  for (const auto& warning : result["warnings"]) {
    warned |= warning.get<std::string>().rfind(
                  "the odometry at the selected images turns enough (", 0) == 0;
  }
  EXPECT_TRUE(warned) << result["warnings"];
}

// `run --force` through a (fake) COLMAP that reconstructs the straight
// drive: the stage lists what it wrote, without the empty outputs.
TEST_F(Excitation, RunListsOnlyOutputsWithContent) {
  const SimulatedDrive drive = WriteDrive(/*straight=*/true);
  const std::string model = WriteModel(drive);
  const std::string path = WriteMappingColmap(model);
  const CommandResult run = RunOdomcal(RunCommand({"--force"}), {{path}});
  EXPECT_EQ(run.exit_code, 3) << run.out << run.err;
  EXPECT_NE(run.out.find(" ... wrote calibration.json, calibration.yaml, "
                         "sparse/, report.html ("),
            std::string::npos)
      << run.out;
  EXPECT_TRUE(fs::exists(dir_ / "ws" / "sparse" / "0" / "images.bin"));
  EXPECT_FALSE(fs::exists(dir_ / "ws" / "sparse_metric"));
  EXPECT_FALSE(fs::exists(dir_ / "ws" / "camera_in_odom.tum"));
  EXPECT_NE(run.out.find("odomcal run: not a calibration (unobservable): "),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("  report: " + Path("ws/report.html") + "\n"),
            std::string::npos)
      << run.out;
}

}  // namespace
}  // namespace odomcal
