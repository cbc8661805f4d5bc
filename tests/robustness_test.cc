// Bad inputs to the odomcal executable, one test per row of
// docs/robustness.md: each asserts the exact error line (or the result
// status) and the exit code. Rows already checked elsewhere are listed in
// that document with their own tests.
//
// The executable is started with fork/exec (no shell) so that a test can
// change its PATH or limit the size of the files it may write.

#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/test_support.h"
#include "odomcal/adapters/timestamp.h"
#include "odomcal/adapters/trajectory_io.h"
#include "odomcal/datasets/simulation/drive_simulator.h"
#include "odomcal/solver/angles.h"
#include "odomcal/tests/odomcal_process.h"
#include "odomcal/tests/test_files.h"

#include <poll.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sqlite3.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace odomcal {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr char kCalibrateError[] = "odomcal calibrate: error: ";
constexpr char kColmapError[] = "odomcal colmap: error: ";
constexpr char kRunError[] = "odomcal run: error: ";

// No NaN or Inf written as a number (OpenCV's YAML spells them .nan, .inf).
void ExpectNoNonFiniteText(const std::string& text) {
  std::string lower = text;
  std::transform(
      lower.begin(), lower.end(), lower.begin(), [](unsigned char c) {
        return std::tolower(c);
      });
  for (const char* word : {"nan", "inf"}) {
    size_t pos = 0;
    while ((pos = lower.find(word, pos)) != std::string::npos) {
      // "inf" inside a word ("information") is text, not a number.
      const bool alone =
          (pos == 0 ||
           !std::isalpha(static_cast<unsigned char>(lower[pos - 1]))) &&
          (pos + 3 >= lower.size() ||
           !std::isalpha(static_cast<unsigned char>(lower[pos + 3])));
      EXPECT_FALSE(alone) << "non-finite number at byte " << pos << ":\n"
                          << text;
      pos += 3;
    }
  }
}

// Exit code 4 (COLMAP missing, failed or gave no model) and exactly `line`
// on stderr.
void ExpectColmapFailure(const CommandResult& run, const std::string& line) {
  EXPECT_EQ(run.exit_code, 4) << run.out << run.err;
  EXPECT_EQ(run.err, line + "\n");
}

// "000042.png": the name of test image `index`.
std::string ImageName(size_t index) {
  char name[32];
  std::snprintf(name, sizeof(name), "%06zu.png", index);
  return name;
}

// Image ImageName(index) of camera 1 at `world_from_cam`.
ColmapImage MakeColmapImage(uint32_t image_id,
                            size_t index,
                            const Rigid3d& world_from_cam) {
  ColmapImage image;
  image.image_id = image_id;
  image.camera_id = 1;
  image.name = ImageName(index);
  image.cam_from_world = Inverse(world_from_cam);
  return image;
}

bool ContainsName(const json& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// Replaces line `line_number` (1-based) of the text file at `path`.
void ReplaceLine(const fs::path& path,
                 int line_number,
                 const std::string& text) {
  std::istringstream in(ReadFile(path));
  std::string line, result;
  for (int k = 1; std::getline(in, line); ++k) {
    result += (k == line_number ? text : line) + "\n";
  }
  WriteFile(path, result);
}

std::string Line(const fs::path& path, int line_number) {
  std::istringstream in(ReadFile(path));
  std::string line;
  for (int k = 1; k <= line_number; ++k) std::getline(in, line);
  return line;
}

// A robot path integrated from its speed (m/s) and yaw rate (rad/s) at time
// t: odometry at 50 Hz, and the camera of the simulator's default mount at
// 10 Hz in an SfM frame of kMetricScale metres per unit. No noise: the two
// files agree exactly, so what a test sees comes from the motion alone.
constexpr double kMetricScale = 0.37;
struct PathFiles {
  Trajectory odometry;
  Trajectory camera;
};
PathFiles IntegratePath(
    const std::function<Eigen::Vector2d(double)>& speed_and_yaw_rate,
    double duration_s) {
  const Rigid3d odom_from_cam = DriveSimulatorOptions().odom_from_cam;
  constexpr double kStep = 0.02;
  constexpr int64_t kStart = 1700000000000000000;
  PathFiles files;
  files.odometry.planar = true;
  double x = 0.0, y = 0.0, yaw = 0.0;
  const int num_steps = static_cast<int>(std::lround(duration_s / kStep));
  for (int k = 0; k <= num_steps; ++k) {
    StampedPose odometry;
    odometry.stamp_ns = kStart + static_cast<int64_t>(k) * 20000000;
    odometry.world_from_sensor =
        Rigid3d(YawRotation(yaw), Eigen::Vector3d(x, y, 0.0));
    files.odometry.poses.push_back(odometry);
    if (k % 5 == 0) {
      StampedPose camera = odometry;
      camera.world_from_sensor = odometry.world_from_sensor * odom_from_cam;
      camera.world_from_sensor.translation /= kMetricScale;
      files.camera.poses.push_back(camera);
    }
    const Eigen::Vector2d v_w = speed_and_yaw_rate(k * kStep);
    const double mid_yaw = yaw + 0.5 * v_w(1) * kStep;
    x += v_w(0) * kStep * std::cos(mid_yaw);
    y += v_w(0) * kStep * std::sin(mid_yaw);
    yaw += v_w(1) * kStep;
  }
  return files;
}

class Robustness : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(::testing::TempDir()) /
           (std::string("odomcal_robust_") + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (std::getenv("ODOMCAL_KEEP_TEST_FILES") == nullptr) fs::remove_all(dir_);
  }

  std::string Path(const std::string& name) const {
    return (dir_ / name).string();
  }

  // camera.tum and odometry.csv of a 60 s simulated drive with turns.
  SimulatedDrive WriteDrive(uint64_t seed = 1) const {
    DriveSimulatorOptions options;
    options.seed = seed;
    options.camera_rotation_noise_deg = 0.01;
    options.camera_position_noise = 0.0005;
    const SimulatedDrive drive = SimulateDrive(options);
    WriteTumTrajectory(drive.camera, Path("camera.tum"));
    WriteOdometryCsv(drive.odometry, Path("odometry.csv"));
    return drive;
  }

  void WritePath(const PathFiles& files) const {
    WriteTumTrajectory(files.camera, Path("camera.tum"));
    WriteOdometryCsv(files.odometry, Path("odometry.csv"));
  }

  std::vector<std::string> Calibrate(
      const std::string& output = "result.json") const {
    return {"calibrate",
            "--camera_poses",
            Path("camera.tum"),
            "--odometry",
            Path("odometry.csv"),
            "--output",
            Path(output)};
  }

  // project/sparse/0 (one binary sub-model of every second camera pose of a
  // simulated drive), project/image_timestamps.csv and odometry.csv.
  void WriteColmapProject(ColmapFormat format = ColmapFormat::kBinary) const {
    const SimulatedDrive drive = WriteDrive(2);
    ColmapModel model;
    model.cameras[1] = MakeColmapCamera(
        1, ColmapCameraModel::kPinhole, 320, 240, {260, 260, 160, 120});
    fs::create_directories(dir_ / "project" / "sparse" / "0");
    std::ofstream stamps(dir_ / "project" / "image_timestamps.csv");
    stamps << "image_name,timestamp\n";
    for (size_t i = 0; i < drive.camera.poses.size(); i += 2) {
      const uint32_t id = static_cast<uint32_t>(i + 1);
      model.images[id] =
          MakeColmapImage(id, i, drive.camera.poses[i].world_from_sensor);
      stamps << ImageName(i) << ","
             << FormatTimestampSeconds(drive.camera.poses[i].stamp_ns) << "\n";
    }
    WriteColmapModel(
        model, (dir_ / "project" / "sparse" / "0").string(), format);
  }

  std::string Model(const std::string& file) const {
    return (dir_ / "project" / "sparse" / "0" / file).string();
  }

  std::vector<std::string> Colmap(const std::string& output = "out") const {
    return {"colmap",
            "--model_path",
            (dir_ / "project" / "sparse").string(),
            "--odometry",
            Path("odometry.csv"),
            "--image_timestamps",
            (dir_ / "project" / "image_timestamps.csv").string(),
            "--output_path",
            Path(output)};
  }

  // images/ with `count` files of the drive's camera times every 1 s,
  // image_timestamps.csv and odometry.csv, for `odomcal run`. The files hold
  // `contents` (not necessarily an image).
  SimulatedDrive WriteImageFolder(int count,
                                  const std::string& contents) const {
    const SimulatedDrive drive = WriteDrive(3);
    fs::create_directories(dir_ / "images");
    std::ofstream stamps(Path("image_timestamps.csv"));
    for (int i = 0; i < count; ++i) {
      const std::string name = ImageName(static_cast<size_t>(i));
      WriteFile(dir_ / "images" / name, contents);
      stamps << name << ","
             << FormatTimestampSeconds(drive.camera.poses[10 * i + 10].stamp_ns)
             << "\n";
    }
    return drive;
  }

  // models/<name>/: the model COLMAP's mapper would make of WriteImageFolder's
  // images first .. count - 1 (the drive's camera poses, no points), with the
  // images `misregistered` 3 deg off about their own x axis.
  // With `num_points`, every image sees points 0 .. num_points - 1.
  void WriteMapperModel(const SimulatedDrive& drive,
                        int count,
                        const std::string& name,
                        const std::vector<int>& misregistered = {},
                        int first = 0,
                        int num_points = 0) const {
    ColmapModel model;
    model.cameras[1] = MakeColmapCamera(
        1, ColmapCameraModel::kPinhole, 320, 240, {260, 260, 160, 120});
    for (int i = first; i < count; ++i) {
      const uint32_t id = static_cast<uint32_t>(i + 1);
      ColmapImage image =
          MakeColmapImage(id,
                          static_cast<size_t>(i),
                          drive.camera.poses[10 * i + 10].world_from_sensor);
      if (std::find(misregistered.begin(), misregistered.end(), i) !=
          misregistered.end()) {
        image.cam_from_world.rotation =
            Eigen::AngleAxisd(3.0 * kPi / 180.0, Eigen::Vector3d::UnitX()) *
            image.cam_from_world.rotation;
      }
      for (int p = 0; p < num_points; ++p) {
        image.points2D.push_back({Eigen::Vector2d(p, p), p});
        model.points3D[p].point3D_id = p;
        model.points3D[p].track.push_back({id, static_cast<uint32_t>(p)});
      }
      model.images[id] = image;
    }
    fs::create_directories(dir_ / "models" / name);
    WriteColmapModel(
        model, (dir_ / "models" / name).string(), ColmapFormat::kBinary);
  }

  // bin/colmap whose mapper copies models/seed_<--random_seed>/ (on the
  // matches of database_rematched.db: models/rematch_seed_<...>/) to
  // <--output_path>/0 (its sub-models 0, 1, ... to <--output_path>/ when
  // it has them), or writes nothing when there is no such model.
  // With `chunks_side_by_side`, the mapper of chunk 0 gives no model
  // unless chunk 1's mapper starts while it runs (it waits up to 20 s).
  // With `adjusts`, point_triangulator copies models/triangulated/ (when
  // the test wrote one: the points it would triangulate) or else its
  // --input_path model to its --output_path, and bundle_adjuster copies its
  // input unchanged (an adjustment that finds the poses it was given right);
  // without, they write nothing.
  std::string WriteFakeColmapWithMapperModels(bool chunks_side_by_side = false,
                                              bool adjusts = false) const {
    const std::string mark = Path("chunk_1_started");
    const std::string wait_for_chunk_1 =
        chunks_side_by_side
            ? "  case \"$out\" in */chunk_1) touch " + mark +
                  ";;\n"
                  "    */chunk_0) i=0; while [ ! -f " +
                  mark +
                  " ]; do i=$((i+1)); [ $i -gt 200 ] && exit 3; sleep 0.1; "
                  "done;; esac\n"
            : std::string();
    return WriteFakeColmap(
        "if [ \"$1\" = feature_extractor ]; then cp " +
        WritePreparedDatabase() +
        " \"$3\"; fi\n"
        "if [ \"$1\" = mapper ]; then\n"
        "  while [ $# -gt 0 ]; do\n"
        "    case \"$1\" in --output_path) out=\"$2\";; --random_seed) "
        "seed=\"$2\";;\n"
        "      --database_path) case \"$2\" in *rematched.db) round=rematch_;; "
        "esac;; esac\n"
        "    shift\n"
        "  done\n" +
        wait_for_chunk_1 + "  model=" + Path("models") +
        "/${round}seed_$seed\n"
        "  if [ -d \"$model/0\" ]; then cp -r \"$model\"/* \"$out/\";\n"
        "  elif [ -d \"$model\" ]; then mkdir -p \"$out/0\" && cp \"$model\"/* "
        "\"$out/0/\"; fi\n"
        "fi\n" +
        (adjusts ? "case \"$1\" in point_triangulator|bundle_adjuster)\n"
                   "  [ \"$1\" = point_triangulator ] && [ -d " +
                       Path("models/triangulated") +
                       " ] && triangulated=" + Path("models/triangulated") +
                       "\n"
                       "  while [ $# -gt 0 ]; do\n"
                       "    case \"$1\" in --input_path) in=\"$2\";; "
                       "--output_path) out=\"$2\";; esac\n"
                       "    shift\n"
                       "  done\n"
                       "  cp \"${triangulated:-$in}\"/* \"$out\"/;;\n"
                       "esac\n"
                 : std::string()) +
        "exit 0\n");
  }

  // `odomcal run` with `bin`'s COLMAP on WriteImageFolder's drive, every
  // image kept (no frame spacing), in chunks of at most 50. The last image
  // lies on the odometry's last sample: a clock offset estimated
  // microseconds positive would leave it out of the metric model (and name
  // it), which is not what these tests are about, so the offset is not
  // estimated.
  CommandResult RunInChunksOf50(const std::string& bin,
                                int num_threads = 1) const {
    std::vector<std::string> command = RunCommand({"--matcher",
                                                   "sequential",
                                                   "--estimate_time_offset",
                                                   "off",
                                                   "--chunk_images",
                                                   "50",
                                                   "--frame_min_translation_m",
                                                   "0",
                                                   "--frame_min_rotation_deg",
                                                   "0"});
    *(std::find(command.begin(), command.end(), "--num_threads") + 1) =
        std::to_string(num_threads);
    return RunOdomcal(command, {{"PATH=" + bin + ":/usr/bin:/bin"}});
  }

  // The angle between the result's odom_from_cam rotation and the drive's.
  static double ExtrinsicRotationError(const json& result,
                                       const SimulatedDrive& drive) {
    const json& q = result["odom_from_cam"]["quaternion_wxyz"];
    return RotationAngle(
        Eigen::Quaterniond(q[0], q[1], q[2], q[3]).conjugate() *
        drive.odom_from_cam.rotation);
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
                                          "--workspace_path",
                                          Path("ws"),
                                          "--num_threads",
                                          "1"};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    return arguments;
  }

  // bin/colmap: prints COLMAP 3.8's banner for `help`; for a subcommand,
  // runs `body` (sh) with the subcommand in $1.
  std::string WriteFakeColmap(const std::string& body) const {
    fs::create_directories(dir_ / "bin");
    const fs::path script = dir_ / "bin" / "colmap";
    WriteFile(
        script,
        "#!/bin/sh\n"
        "if [ \"$1\" = help ]; then\n"
        "  echo 'COLMAP 3.8 -- Structure-from-Motion and Multi-View Stereo'\n"
        "  exit 0\n"
        "fi\n" +
            body);
    ::chmod(script.c_str(), 0755);
    return (dir_ / "bin").string();
  }

  // prepared.db: a database with the cameras and images tables of COLMAP 3.8
  // holding one 320x240 PINHOLE camera and every image of images/, as
  // feature_extractor would leave it.
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
        // 260, 260, 160, 120 as little-endian float64.
        "INSERT INTO cameras VALUES (1, 1, 320, 240, "
        "X'0000000000407040000000000040704000000000000064400000000000005e40', "
        "1);";
    int id = 1;
    for (const auto& entry : fs::directory_iterator(dir_ / "images")) {
      sql += "INSERT INTO images (image_id, name, camera_id) VALUES (" +
             std::to_string(id++) + ", '" + entry.path().filename().string() +
             "', 1);";
    }
    EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr),
              SQLITE_OK)
        << sqlite3_errmsg(db);
    sqlite3_close(db);
    return path;
  }

  fs::path dir_;
};

// ---------------------------------------------------------------------------
// Input files that cannot be read.

TEST_F(Robustness, MissingInputFile) {
  WriteDrive();
  std::vector<std::string> arguments = Calibrate();
  arguments[2] = Path("missing.tum");
  ExpectBadInput(
      RunOdomcal(arguments),
      std::string(kCalibrateError) +
          "--camera_poses: File does not exist: " + Path("missing.tum"));
  EXPECT_FALSE(fs::exists(Path("result.json")));
}

// As root every file is readable, so a folder given as a file and a file
// whose read() fails (/proc/self/mem at offset 0: EIO) stand in for a file
// without read permission; that case runs only when not root.
TEST_F(Robustness, UnreadableInputFile) {
  WriteDrive();
  fs::create_directories(Path("folder.csv"));
  std::vector<std::string> arguments = Calibrate();
  arguments[4] = Path("folder.csv");
  ExpectBadInput(
      RunOdomcal(arguments),
      std::string(kCalibrateError) +
          "--odometry: File is actually a directory: " + Path("folder.csv"));

  arguments[4] = "/proc/self/mem";
  ExpectBadInput(RunOdomcal(arguments),
                 std::string(kCalibrateError) + "/proc/self/mem:1: read error");

  if (::geteuid() != 0) {
    ::chmod(Path("odometry.csv").c_str(), 0);
    arguments[4] = Path("odometry.csv");
    ExpectBadInput(RunOdomcal(arguments),
                   std::string(kCalibrateError) + Path("odometry.csv") +
                       ": cannot open for reading: Permission denied");
  }
  EXPECT_FALSE(fs::exists(Path("result.json")));
}

// ---------------------------------------------------------------------------
// COLMAP models.

TEST_F(Robustness, TruncatedColmapBinary) {
  WriteColmapProject();
  const std::string bytes = ReadFile(Model("images.bin"));
  // Cut early: the image count no longer fits in what is left.
  WriteFile(Model("images.bin"), bytes.substr(0, 100));
  ExpectBadInput(
      RunOdomcal(Colmap()),
      std::string(kColmapError) + Model("images.bin") +
          ": byte 0: number of images is 301, but the 92 remaining bytes "
          "hold at most 1 (garbled or truncated file)");
  // Cut inside the last record.
  WriteFile(Model("images.bin"), bytes.substr(0, bytes.size() - 3));
  ExpectBadInputContaining(
      RunOdomcal(Colmap()),
      std::string(kColmapError) + Model("images.bin") + ": byte ",
      {": image 301 of 301 (image_id 601, '000600.png'): truncated: "
       "number of points2D needs 8 bytes, 5 remain"});
  EXPECT_FALSE(fs::exists(Path("out/calibration.json")));
}

TEST_F(Robustness, ColmapBinaryCountLargerThanTheFile) {
  WriteColmapProject();
  std::string bytes = ReadFile(Model("images.bin"));
  const uint64_t huge = uint64_t{1} << 60;
  bytes.replace(
      0, 8, reinterpret_cast<const char*>(&huge), 8);  // little-endian host
  WriteFile(Model("images.bin"), bytes);
  ExpectBadInputContaining(
      RunOdomcal(Colmap()),
      std::string(kColmapError) + Model("images.bin") + ": byte 0: ",
      {"number of images is 1152921504606846976",
       "remaining bytes hold at most"});
}

TEST_F(Robustness, UnknownColmapCameraModelId) {
  WriteColmapProject();
  std::string bytes = ReadFile(Model("cameras.bin"));
  const uint32_t model_id = 99;
  bytes.replace(12, 4, reinterpret_cast<const char*>(&model_id), 4);
  WriteFile(Model("cameras.bin"), bytes);
  ExpectBadInput(
      RunOdomcal(Colmap()),
      std::string(kColmapError) + Model("cameras.bin") +
          ": byte 12: camera 1 of 1 (camera_id 1): unknown camera model id 99 "
          "(COLMAP 3.8 to 4.1 models are 0 to 17)");
}

TEST_F(Robustness, ColmapTextWrongColumnCount) {
  WriteColmapProject(ColmapFormat::kText);
  // images.txt: 4 comment lines, then the first image's pose line.
  std::string pose = Line(Model("images.txt"), 5);
  ReplaceLine(Model("images.txt"), 5, pose.substr(0, pose.rfind(' ')));
  ExpectBadInput(RunOdomcal(Colmap()),
                 std::string(kColmapError) + Model("images.txt") +
                     ":5: expected 10 fields (IMAGE_ID QW QX QY QZ TX TY TZ "
                     "CAMERA_ID NAME; names cannot contain blanks), got 9");
  WriteColmapProject(ColmapFormat::kText);
  ReplaceLine(Model("cameras.txt"), 4, "1 PINHOLE 320");
  ExpectBadInput(
      RunOdomcal(Colmap("out2")),
      std::string(kColmapError) + Model("cameras.txt") +
          ":4: expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS[], got 3 fields");
}

// ---------------------------------------------------------------------------
// TUM and CSV trajectories. odometry.csv has a header on line 1; camera.tum
// has one comment line.

TEST_F(Robustness, NanOrInfInTrajectory) {
  WriteDrive();
  ReplaceLine(Path("odometry.csv"), 10, "1700000000.180000000,nan,0,0");
  ExpectBadInput(RunOdomcal(Calibrate()),
                 std::string(kCalibrateError) + Path("odometry.csv") +
                     ":10: column 'x' is not finite (NaN or Inf): 'nan'");
  WriteDrive();
  ReplaceLine(Path("camera.tum"), 3, "1700000000.100000000 0 0 0 0 0 0 inf");
  ExpectBadInput(RunOdomcal(Calibrate()),
                 std::string(kCalibrateError) + Path("camera.tum") +
                     ":3: column 'qw' is not finite (NaN or Inf): 'inf'");
  EXPECT_FALSE(fs::exists(Path("result.json")));
}

TEST_F(Robustness, NonNumericField) {
  WriteDrive();
  ReplaceLine(Path("odometry.csv"), 10, "1700000000.180000000,0,0,north");
  ExpectBadInput(RunOdomcal(Calibrate()),
                 std::string(kCalibrateError) + Path("odometry.csv") +
                     ":10: column 'yaw' is not a number: 'north'");
  WriteDrive();
  ReplaceLine(Path("camera.tum"), 3, "yesterday 0 0 0 0 0 0 1");
  ExpectBadInput(
      RunOdomcal(Calibrate()),
      std::string(kCalibrateError) + Path("camera.tum") +
          ":3: column 'timestamp': 'yesterday' is not a decimal number");
}

TEST_F(Robustness, FewerColumns) {
  WriteDrive();
  ReplaceLine(Path("odometry.csv"), 10, "1700000000.180000000,0,0");
  ExpectBadInput(RunOdomcal(Calibrate()),
                 std::string(kCalibrateError) + Path("odometry.csv") +
                     ":10: expected 4 fields (timestamp,x,y,yaw), got 3");
  WriteDrive();
  ReplaceLine(Path("camera.tum"), 3, "1700000000.100000000 0 0 0 0 0 1");
  ExpectBadInput(
      RunOdomcal(Calibrate()),
      std::string(kCalibrateError) + Path("camera.tum") +
          ":3: expected 8 fields (timestamp tx ty tz qx qy qz qw), got 7");
}

TEST_F(Robustness, UnsortedTimestamps) {
  WriteDrive();
  const std::string line_10 = Line(Path("odometry.csv"), 10);
  ReplaceLine(Path("odometry.csv"), 10, Line(Path("odometry.csv"), 11));
  ReplaceLine(Path("odometry.csv"), 11, line_10);
  ExpectBadInput(
      RunOdomcal(Calibrate()),
      std::string(kCalibrateError) + Path("odometry.csv") +
          ":11: timestamp not increasing: 1700000000.160000000 after "
          "1700000000.180000000 on line 10");
}

TEST_F(Robustness, DuplicateTimestamps) {
  WriteDrive();
  const std::string line_3 = Line(Path("camera.tum"), 3);
  ReplaceLine(Path("camera.tum"), 4, line_3);
  ExpectBadInput(RunOdomcal(Calibrate()),
                 std::string(kCalibrateError) + Path("camera.tum") +
                     ":4: duplicate timestamp 1700000000.100000000 after "
                     "1700000000.100000000 on line 3");
}

// Nanosecond stamps in a file declared as seconds (the default).
TEST_F(Robustness, TimestampsInAnotherUnit) {
  WriteDrive();
  ReplaceLine(Path("odometry.csv"), 2, "1700000000000000000,0,0,0");
  ExpectBadInput(
      RunOdomcal(Calibrate()),
      std::string(kCalibrateError) + Path("odometry.csv") +
          ":2: column 'timestamp': timestamp 1700000000000000000 looks like "
          "nanoseconds or microseconds but the time unit is seconds; pass the "
          "time unit flag");
  // Seconds declared as nanoseconds.
  WriteDrive();
  std::vector<std::string> arguments = Calibrate();
  arguments.insert(arguments.end(), {"--camera_time_unit", "ns"});
  ExpectBadInput(
      RunOdomcal(arguments),
      std::string(kCalibrateError) + Path("camera.tum") +
          ":3: column 'timestamp': timestamp '1700000000.100000000' has a "
          "fractional part but the time unit is ns; pass the time unit flag");
}

// ---------------------------------------------------------------------------
// Time coverage.

TEST_F(Robustness, OdometryCoversOnlyPartOfTheImages) {
  const SimulatedDrive drive = WriteDrive();
  Trajectory first_half = drive.odometry;
  first_half.poses.resize(first_half.poses.size() / 2);
  WriteOdometryCsv(first_half, Path("odometry.csv"));
  const CommandResult run = RunOdomcal(Calibrate());
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const json result = json::parse(ReadFile(Path("result.json")));
  EXPECT_EQ(result["status"], "success");
  EXPECT_TRUE(
      ContainsName(result["warnings"],
                   "301 camera poses were skipped: outside the odometry span "
                   "or in gaps longer than 0.25 s"))
      << result["warnings"];
}

TEST_F(Robustness, NoTimeOverlap) {
  WriteDrive();
  std::vector<std::string> arguments = Calibrate();
  arguments.insert(arguments.end(), {"--camera_time_offset_s", "3600"});
  ExpectBadInput(
      RunOdomcal(arguments),
      std::string(kCalibrateError) +
          "no camera timestamp falls inside the odometry (601 outside "
          "its span, 0 in gaps): camera times "
          "1700000000.000-1700000060.000 s (then shifted by 3600.000 s), "
          "odometry 1700000000.000-1700000060.000 s; check the time units "
          "and --camera_time_offset_s");
  EXPECT_FALSE(fs::exists(Path("result.json")));
}

// ---------------------------------------------------------------------------
// Motions that do not determine the calibration.

TEST_F(Robustness, SingleMotion) {
  const SimulatedDrive drive = WriteDrive();
  Trajectory two = drive.camera;
  two.poses = {drive.camera.poses[100], drive.camera.poses[140]};
  WriteTumTrajectory(two, Path("camera.tum"));
  const CommandResult run = RunOdomcal(Calibrate());
  EXPECT_EQ(run.exit_code, 3) << run.out << run.err;
  const json result = json::parse(ReadFile(Path("result.json")));
  EXPECT_EQ(result["status"], "not_enough_motion");
  EXPECT_EQ(result["message"], "only 1 motion pairs; at least 2 are needed");
  EXPECT_TRUE(result["odom_from_cam"].is_null());
  ExpectNoNonFiniteText(ReadFile(Path("result.yaml")));
}

// Turning on the spot at 0.4 rad/s for a minute.
TEST_F(Robustness, PureRotationInPlace) {
  WritePath(
      IntegratePath([](double) { return Eigen::Vector2d(0.0, 0.4); }, 60.0));
  const CommandResult run = RunOdomcal(Calibrate());
  EXPECT_EQ(run.exit_code, 3) << run.out << run.err;
  const json result = json::parse(ReadFile(Path("result.json")));
  EXPECT_EQ(result["status"], "unobservable");
  EXPECT_EQ(
      result["message"],
      "the odometry never translates (largest step 0 m: rotation in place "
      "only): the metric scale and the x/y translation cannot be "
      "determined; drive forward while turning");
  EXPECT_EQ(
      result["unobservable"],
      json::array(
          {"translation_x", "translation_y", "translation_z", "metric_scale"}));
  EXPECT_TRUE(result["metric_scale"].is_null());
  ExpectNoNonFiniteText(ReadFile(Path("result.yaml")));
}

// A circle at constant speed: every keyframe pair is the same motion, with
// the same yaw.
TEST_F(Robustness, AllMotionsWithTheSameYaw) {
  WritePath(
      IntegratePath([](double) { return Eigen::Vector2d(0.3, 0.3); }, 60.0));
  const CommandResult run = RunOdomcal(Calibrate());
  EXPECT_EQ(run.exit_code, 3) << run.out << run.err;
  const json result = json::parse(ReadFile(Path("result.json")));
  EXPECT_EQ(result["status"], "unobservable");
  EXPECT_EQ(
      result["message"],
      "the motion does not determine: rotation, translation_x, translation_y, "
      "metric_scale (standard deviation above the limit or no information; "
      "drive turns of different sizes in both directions)");
  EXPECT_EQ(result["unobservable"],
            json::array({"translation_z",
                         "rotation",
                         "translation_x",
                         "translation_y",
                         "metric_scale"}));
  EXPECT_TRUE(result["metric_scale"].is_null());
  ExpectNoNonFiniteText(ReadFile(Path("result.json")));
  ExpectNoNonFiniteText(ReadFile(Path("result.yaml")));
}

// Every third motion pair's camera motion replaced by a wrong one: two
// consecutive camera poses out of every ten are moved, which spoils the
// three pairs that touch them.
TEST_F(Robustness, ThirtyPercentOutlierCameraMotions) {
  const SimulatedDrive drive = WriteDrive();
  Trajectory camera = drive.camera;
  for (size_t i = 0; i < camera.poses.size(); ++i) {
    if (i % 10 == 4 || i % 10 == 5) {
      Rigid3d& pose = camera.poses[i].world_from_sensor;
      pose.rotation =
          pose.rotation * ExpRotation(Eigen::Vector3d(0.2, -0.3, 0.1) *
                                      (i % 10 == 4 ? 1.0 : -1.0));
      pose.translation +=
          Eigen::Vector3d(0.5, 0.3, -0.2) * (i % 10 == 4 ? 1.0 : -1.0);
    }
  }
  WriteTumTrajectory(camera, Path("camera.tum"));
  std::vector<std::string> arguments = Calibrate();
  // Every camera pose a keyframe, so that the outliers are 30 % of the pairs.
  arguments.insert(arguments.end(),
                   {"--keyframe_min_rotation_deg",
                    "0",
                    "--keyframe_min_translation_m",
                    "0"});
  const CommandResult run = RunOdomcal(arguments);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const json result = json::parse(ReadFile(Path("result.json")));
  EXPECT_EQ(result["status"], "success");
  // Every spoiled pair (those touching poses 4 and 5 of ten) rejected; of
  // the 420 good ones the 99.9 % chi-square gate may reject a few by chance
  // (0.4 expected).
  const json& inliers = result["diagnostics"]["inlier_mask"];
  ASSERT_EQ(inliers.size(), 600u);
  int good_rejected = 0;
  for (size_t i = 0; i < inliers.size(); ++i) {
    const bool spoiled = i % 10 == 3 || i % 10 == 4 || i % 10 == 5;
    if (spoiled) {
      EXPECT_FALSE(inliers[i].get<bool>()) << "pair " << i;
    } else {
      good_rejected += !inliers[i].get<bool>();
    }
  }
  EXPECT_LE(good_rejected, 2);
  const int used = 420 - good_rejected;
  EXPECT_EQ(result["message"],
            "calibrated from " + std::to_string(used) + " of 600 motion pairs");
  EXPECT_TRUE(ContainsName(
      result["warnings"],
      std::to_string(600 - used) + " of 600 motion pairs rejected as outliers"))
      << result["warnings"];
  const auto& q = result["odom_from_cam"]["quaternion_wxyz"];
  const Eigen::Quaterniond rotation(q[0], q[1], q[2], q[3]);
  // The inliers carry 0.01 deg camera noise.
  EXPECT_LT(RotationAngle(rotation.conjugate() * drive.odom_from_cam.rotation) *
                180.0 / kPi,
            0.1);
}

// Positions near the largest double: each file value is finite, but the
// differences between poses overflow. The solver's guard names it.
TEST_F(Robustness, FiniteInputsWhoseMotionsOverflow) {
  const SimulatedDrive drive = WriteDrive();
  Trajectory camera = drive.camera;
  for (size_t i = 0; i < camera.poses.size(); ++i) {
    camera.poses[i].world_from_sensor.translation.x() =
        (i % 2 == 0 ? 1.7e308 : -1.7e308);
  }
  WriteTumTrajectory(camera, Path("camera.tum"));
  const CommandResult run = RunOdomcal(Calibrate());
  ExpectBadInput(
      run,
      std::string(kCalibrateError) + "motion pair 0 has a non-finite value");
  // Finite steps whose squares overflow.
  for (size_t i = 0; i < camera.poses.size(); ++i) {
    camera.poses[i].world_from_sensor.translation.x() =
        (i % 2 == 0 ? 1e200 : -1e200);
  }
  WriteTumTrajectory(camera, Path("camera.tum"));
  ExpectBadInput(
      RunOdomcal(Calibrate()),
      std::string(kCalibrateError) +
          "motion pair 0 has a translation too large to square in double "
          "precision (check the units)");
  EXPECT_FALSE(fs::exists(Path("result.json")));
}

// ---------------------------------------------------------------------------
// odomcal run and COLMAP.

TEST_F(Robustness, ColmapMissingFromPath) {
  WriteImageFolder(5, "x");
  ExpectColmapFailure(
      RunOdomcal(RunCommand(), {{"PATH=" + Path("empty_bin")}}),
      std::string(kRunError) +
          "COLMAP not found: 'colmap' is not an executable on PATH (install "
          "Debian's colmap package or pass --colmap_path)");
}

// Extraction and matching succeed, the mapper aborts on a failed CHECK
// (exit 134) and prints glog's stack trace after it.
TEST_F(Robustness, ColmapAbortsMidRun) {
  WriteImageFolder(5, "x");
  const std::string bin = WriteFakeColmap(
      "if [ \"$1\" = feature_extractor ]; then cp " + WritePreparedDatabase() +
      " \"$3\"; fi\n"
      "if [ \"$1\" = mapper ]; then\n"
      "  echo 'F0101 mapper.cc:1] Check failed: reconstruction' >&2\n"
      "  echo '*** Check failure stack trace: ***' >&2\n"
      "  echo '    @     0x55aebb39816f  colmap::IncrementalMapper::Run()' "
      ">&2\n"
      "  exit 134\n"
      "fi\n"
      "exit 0\n");
  const CommandResult run = RunOdomcal(RunCommand({"--matcher", "sequential"}),
                                       {{"PATH=" + bin + ":/usr/bin:/bin"}});
  ExpectColmapFailure(
      run,
      std::string(kRunError) +
          "COLMAP mapper failed with exit code 134 (COLMAP aborted on a "
          "failed CHECK); see " +
          Path("ws/logs/mapper_seed_0.log") +
          " (last line: F0101 mapper.cc:1] Check failed: reconstruction)");
}

// COLMAP exits 0 but writes nothing: caught after the first stage; and a
// mapper that exits 0 without a model.
TEST_F(Robustness, ColmapProducesNoModel) {
  WriteImageFolder(5, "x");
  std::string bin = WriteFakeColmap("exit 0\n");
  CommandResult run = RunOdomcal(RunCommand({"--matcher", "sequential"}),
                                 {{"PATH=" + bin + ":/usr/bin:/bin"}});
  ExpectColmapFailure(run,
                      std::string(kRunError) +
                          "COLMAP feature_extractor wrote no database " +
                          Path("ws/database.db") + " (see " +
                          Path("ws/logs/feature_extractor.log") + ")");

  bin = WriteFakeColmap("if [ \"$1\" = feature_extractor ]; then cp " +
                        WritePreparedDatabase() + " \"$3\"; fi\nexit 0\n");
  run = RunOdomcal(RunCommand({"--matcher", "sequential"}),
                   {{"PATH=" + bin + ":/usr/bin:/bin"}});
  ExpectColmapFailure(
      run,
      std::string(kRunError) +
          "COLMAP mapper produced no model in 3 runs (see " +
          Path("ws/logs/mapper_seed_0.log") +
          "): too little texture or overlap, or wrong intrinsics");
}

// COLMAP's mapper returns, for one random seed, no model, for another a model
// with two images registered 3 deg off (the odometry contradicts the motion
// pairs around them), for a third a clean one: odomcal maps with seeds 0, 1,
// 2 and calibrates the clean model, copied to sparse/.
TEST_F(Robustness, MapperRunsAgainWhileTheOdometryContradictsItsModel) {
  constexpr int kImages = 30;
  const SimulatedDrive drive = WriteImageFolder(kImages, "x");
  WriteMapperModel(drive, kImages, "seed_1", {7, 19});
  WriteMapperModel(drive, kImages, "seed_2");
  const std::string bin = WriteFakeColmapWithMapperModels();
  const CommandResult run = RunOdomcal(RunCommand({"--matcher", "sequential"}),
                                       {{"PATH=" + bin + ":/usr/bin:/bin"}});
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("--random_seed 1 ... done"), std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("contradict the odometry: mapping again"),
            std::string::npos)
      << run.out;
  const json result = json::parse(ReadFile(Path("ws/calibration.json")));
  EXPECT_EQ(result["status"], "success");
  // The default frame spacing follows the narrower (here the vertical)
  // field of view of --camera_params 260,260,160,120: 2 atan(120 / 260).
  const double fov_deg = 2.0 * std::atan(120.0 / 260.0) * kRadToDeg;
  EXPECT_NEAR(result["options"]["run"]["frame_min_rotation_deg"].get<double>(),
              fov_deg / 8.0,
              1e-9);
  EXPECT_NEAR(result["options"]["run"]["frame_min_translation_m"].get<double>(),
              2.5 * std::tan(fov_deg / 16.0 * kDegToRad),
              1e-9);
  const json& attempts = result["colmap"]["mapper_attempts"];
  ASSERT_EQ(attempts.size(), 3u) << attempts.dump(2);
  EXPECT_FALSE(attempts[0]["produced_model"]);
  EXPECT_TRUE(attempts[1]["produced_model"]);
  EXPECT_GT(attempts[1]["num_contradicting_pairs"], 0) << attempts.dump(2);
  EXPECT_EQ(attempts[2]["num_contradicting_pairs"], 0) << attempts.dump(2);
  EXPECT_EQ(attempts[2]["num_pairs_used"], attempts[2]["num_motion_pairs"]);
  EXPECT_FALSE(attempts[0]["chosen"]);
  EXPECT_FALSE(attempts[1]["chosen"]);
  EXPECT_TRUE(attempts[2]["chosen"]);
  EXPECT_EQ(ReadFile(dir_ / "ws" / "sparse" / "0" / "images.bin"),
            ReadFile(dir_ / "models" / "seed_2" / "images.bin"));
  EXPECT_EQ(result["colmap"]["sub_models"][0]["path"], Path("ws/sparse/0"));
  EXPECT_LT(ExtrinsicRotationError(result, drive), 0.1 * kPi / 180.0);
}

// A drive of more selected images than --chunk_images is mapped in chunks
// (mapper_chunks.h): 60 images, chunks of at most 50 sharing 12: images
// 1-37 and 24-60, each mapped once (--random_seed 0; the fake mapper gives
// the whole drive's model both times), each cut to its own images (1-30,
// 30-60: the overlap split in the middle, one image shared) as a sub-model
// of its own; the calibration of the two segments recovers the extrinsic.
TEST_F(Robustness, LongDriveIsMappedInChunks) {
  constexpr int kImages = 60;
  const SimulatedDrive drive = WriteImageFolder(kImages, "x");
  WriteMapperModel(drive, kImages, "seed_0");
  const std::string bin = WriteFakeColmapWithMapperModels(true);
  const CommandResult run = RunInChunksOf50(bin, 2);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("60 images: mapped in 2 chunks of 37 sharing at "
                         "least 12 images"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("COLMAP mapping chunk 2 of 2 (images 24-60)"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("60 of 37 images registered, 31 of the chunk's own "
                         "31 kept"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("calibrating against the odometry (models of the 2 "
                         "chunks)"),
            std::string::npos)
      << run.out;
  // --num_threads 2: both chunks mapped side by side (chunk 0's fake
  // mapper gives a model only so), one thread each.
  EXPECT_NE(run.out.find("2 chunks mapped, 2 side by side (--num_threads 2)"),
            std::string::npos)
      << run.out;
  const std::string commands = ReadFile(Path("ws/commands.txt"));
  for (const std::string chunk : {"chunk_0", "chunk_1"}) {
    EXPECT_NE(commands.find("mapper_attempts/" + chunk + " --image_list_path " +
                            Path("ws/chunks/" + chunk + "_images.txt") +
                            " --random_seed 0 --Mapper.num_threads 1 "),
              std::string::npos)
        << commands;
  }
  const json result = json::parse(ReadFile(Path("ws/calibration.json")));
  EXPECT_EQ(result["status"], "success");
  EXPECT_EQ(result["options"]["run"]["chunk_images"], 50);
  const json& sub_models = result["colmap"]["sub_models"];
  ASSERT_EQ(sub_models.size(), 2u) << sub_models.dump(2);
  EXPECT_EQ(sub_models[0]["num_registered_images"], 30);
  EXPECT_EQ(sub_models[1]["num_registered_images"], 31);
  EXPECT_EQ(result["colmap"]["image_coverage"]["num_in_calibration"], 60);
  EXPECT_LT(ExtrinsicRotationError(result, drive), 0.1 * kPi / 180.0);
}

// A chunk whose model COLMAP folded is mapped again with the next seed
// (mapper_chunks.h): with --random_seed 0 the mapper gives two sub-models,
// images 1-15 and 16-60, the second with images 41, 43, 45 and 47 3 deg
// off, so the pairs 40-48 of the second chunk's own images (30-60)
// contradict the odometry as one stretch, left out as folded; the first
// chunk's own images (1-30) are clean. The fold is in the combination's
// third sub-model (the first chunk's two, then the second chunk's one that
// keeps its own images), which came from the second chunk: only that chunk
// is mapped again (--random_seed 1, a clean model), and its new model is
// kept: every image is in the calibration. The fake COLMAP's
// bundle_adjuster writes nothing, so posing the fold from the odometry
// (tried first) fails, and the seeds take over.
TEST_F(Robustness, ChunkWithAFoldedStretchIsMappedAgain) {
  constexpr int kImages = 60;
  const SimulatedDrive drive = WriteImageFolder(kImages, "x");
  WriteMapperModel(drive, 15, "seed_0/0");
  WriteMapperModel(drive, kImages, "seed_0/1", {40, 42, 44, 46}, 15);
  WriteMapperModel(drive, kImages, "seed_1");
  const std::string bin = WriteFakeColmapWithMapperModels();
  const CommandResult run = RunInChunksOf50(bin, 2);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_EQ(run.out.find("COLMAP mapping chunk 1 again"), std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("not posed: colmap bundle_adjuster wrote no model"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("COLMAP mapping chunk 2 again, --random_seed 1 ("),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find(": this model kept"), std::string::npos) << run.out;
  const json result = json::parse(ReadFile(Path("ws/calibration.json")));
  EXPECT_EQ(result["status"], "success");
  const json& attempts = result["colmap"]["mapper_attempts"];
  ASSERT_EQ(attempts.size(), 2u) << attempts.dump(2);
  EXPECT_TRUE(attempts[0]["chunk"].is_null());
  EXPECT_EQ(attempts[0]["random_seed"], 0);
  EXPECT_GE(attempts[0]["num_pairs_left_out"].get<int>(), 3);
  EXPECT_FALSE(attempts[0]["chosen"].get<bool>());
  EXPECT_EQ(attempts[1]["chunk"], 1);
  EXPECT_EQ(attempts[1]["random_seed"], 1);
  // The combination calibrated: chunk 0's model and chunk 1's new one.
  EXPECT_EQ(attempts[1]["path"], Path("ws/mapper_attempts/chunks_1_seed_1"));
  EXPECT_TRUE(fs::exists(Path("ws/mapper_attempts/chunk_1_seed_1/0")));
  EXPECT_EQ(attempts[1]["num_pairs_left_out"], 0);
  EXPECT_TRUE(attempts[1]["chosen"].get<bool>());
  EXPECT_EQ(result["colmap"]["image_coverage"]["num_in_calibration"], 60);
  EXPECT_LT(ExtrinsicRotationError(result, drive), 0.1 * kPi / 180.0);
}

// The same fold, and no seed that would give a model: the folded stretch is
// posed again from the odometry first (images 39 on, from the calibration of
// the first combination), triangulated and adjusted again (the fake keeps the
// poses it is given), and that model is kept without any mapper run again.
TEST_F(Robustness, ChunkWithAFoldedStretchIsPosedFromTheOdometry) {
  constexpr int kImages = 60;
  const SimulatedDrive drive = WriteImageFolder(kImages, "x");
  WriteMapperModel(drive, 15, "seed_0/0");
  WriteMapperModel(drive, kImages, "seed_0/1", {40, 42, 44, 46}, 15);
  WriteMapperModel(drive, kImages, "triangulated", {}, 15, 30);
  const std::string bin = WriteFakeColmapWithMapperModels(false, true);
  const CommandResult run = RunInChunksOf50(bin, 2);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("COLMAP chunk 2: the folded stretch posed from the "
                         "odometry, triangulated and adjusted again ("),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("images from 000039.png on; 0 motion pairs of the "
                         "drive left out as folded (was "),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find(": this model kept"), std::string::npos) << run.out;
  EXPECT_EQ(run.out.find("again, --random_seed"), std::string::npos) << run.out;
  const std::string commands = ReadFile(Path("ws/commands.txt"));
  EXPECT_TRUE(Contains(commands, "point_triangulator")) << commands;
  EXPECT_TRUE(Contains(commands, "--clear_points 1")) << commands;
  EXPECT_TRUE(Contains(commands,
                       "bundle_adjuster --input_path " +
                           Path("ws/mapper_attempts/"
                                "chunk_1_posed_from_odometry/triangulated_0")))
      << commands;
  EXPECT_TRUE(Contains(commands, "--BundleAdjustment.refine_focal_length 0"))
      << commands;
  const json result = json::parse(ReadFile(Path("ws/calibration.json")));
  EXPECT_EQ(result["status"], "success");
  const json& attempts = result["colmap"]["mapper_attempts"];
  ASSERT_EQ(attempts.size(), 2u) << attempts.dump(2);
  EXPECT_FALSE(attempts[0]["posed_from_odometry"].get<bool>());
  EXPECT_GE(attempts[0]["num_pairs_left_out"].get<int>(), 3);
  EXPECT_EQ(attempts[1]["chunk"], 1);
  EXPECT_EQ(attempts[1]["random_seed"], 0);
  EXPECT_TRUE(attempts[1]["posed_from_odometry"].get<bool>());
  EXPECT_EQ(attempts[1]["path"],
            Path("ws/mapper_attempts/chunks_1_posed_from_odometry"));
  EXPECT_EQ(attempts[1]["num_pairs_left_out"], 0);
  EXPECT_TRUE(attempts[1]["chosen"].get<bool>());
  EXPECT_EQ(result["colmap"]["image_coverage"]["num_in_calibration"], 60);
  EXPECT_LT(ExtrinsicRotationError(result, drive), 0.1 * kPi / 180.0);

  // Run again: the same fold posed the same way, so COLMAP's two stages
  // are reused (their output is not written anew) and so is every later
  // stage; the result is the same.
  // A sub-model left from an earlier run with more of them must not be
  // combined.
  const fs::path adjusted =
      Path("ws/mapper_attempts/chunk_1_posed_from_odometry/0/images.bin");
  const auto written = fs::last_write_time(adjusted);
  const fs::path stale =
      Path("ws/mapper_attempts/chunk_1_posed_from_odometry/1");
  fs::copy(adjusted.parent_path(), stale);
  const CommandResult rerun = RunInChunksOf50(bin, 2);
  ASSERT_EQ(rerun.exit_code, 0) << rerun.out << rerun.err;
  EXPECT_EQ(fs::last_write_time(adjusted), written);
  EXPECT_FALSE(fs::exists(stale));
  const json again = json::parse(ReadFile(Path("ws/calibration.json")));
  EXPECT_EQ(again["odom_from_cam"], result["odom_from_cam"]);
  EXPECT_TRUE(again["colmap"]["mapper_attempts"][1]["chosen"].get<bool>());
}

// The same, but the adjustment leaves the posed images without the points
// that would hold them (29 each, one fewer than COLMAP's mapper registers an
// image from): their poses would be the odometry's, agreeing with it by
// construction, so the posed model is not used and the fold stays left out.
TEST_F(Robustness, PosedStretchWithoutPointsToHoldItIsNotUsed) {
  constexpr int kImages = 60;
  const SimulatedDrive drive = WriteImageFolder(kImages, "x");
  WriteMapperModel(drive, 15, "seed_0/0");
  WriteMapperModel(drive, kImages, "seed_0/1", {40, 42, 44, 46}, 15);
  WriteMapperModel(drive, kImages, "triangulated", {}, 15, 29);
  const std::string bin = WriteFakeColmapWithMapperModels(false, true);
  const CommandResult run = RunInChunksOf50(bin, 2);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("sees only 29 triangulated points after the "
                         "adjustment"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("contradicts the odometry: left out"),
            std::string::npos)
      << run.out;
  const json result = json::parse(ReadFile(Path("ws/calibration.json")));
  for (const json& attempt : result["colmap"]["mapper_attempts"]) {
    EXPECT_FALSE(attempt["posed_from_odometry"].get<bool>());
  }
  EXPECT_LT(result["colmap"]["image_coverage"]["num_in_calibration"].get<int>(),
            60);
}

// Where a second seed folds the chunk too (here worse), the fold is the
// scene's: no third seed is tried (it would be clean here), and the first
// model stays, its folded stretch left out and named.
TEST_F(Robustness, ChunkFoldedByTwoSeedsIsNotMappedAThirdTime) {
  constexpr int kImages = 60;
  const SimulatedDrive drive = WriteImageFolder(kImages, "x");
  WriteMapperModel(drive, kImages, "seed_0", {40, 42, 44, 46});
  WriteMapperModel(drive, kImages, "seed_1", {36, 38, 40, 42, 44, 46, 48, 50});
  WriteMapperModel(drive, kImages, "seed_2");
  const std::string bin = WriteFakeColmapWithMapperModels();
  const CommandResult run = RunInChunksOf50(bin);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find(": not better, no further seed"), std::string::npos)
      << run.out;
  EXPECT_EQ(run.out.find("--random_seed 2"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("contradicts the odometry: left out"),
            std::string::npos)
      << run.out;
  const json result = json::parse(ReadFile(Path("ws/calibration.json")));
  const json& attempts = result["colmap"]["mapper_attempts"];
  ASSERT_EQ(attempts.size(), 2u) << attempts.dump(2);
  EXPECT_TRUE(attempts[0]["chosen"].get<bool>());
  EXPECT_EQ(attempts[1]["chunk"], 1);
  EXPECT_FALSE(attempts[1]["chosen"].get<bool>());
  EXPECT_LT(attempts[1]["num_pairs_used"], attempts[0]["num_pairs_used"]);
  // What was calibrated is the first model.
  EXPECT_EQ(result["diagnostics"]["num_pairs_used"],
            attempts[0]["num_pairs_used"]);
  EXPECT_LT(result["colmap"]["image_coverage"]["num_in_calibration"].get<int>(),
            60);
}

// COLMAP reconstructed images 20-29 twice: in sub-model 0 on their own,
// two of them 3 deg off, and in sub-model 1 with all the others. Sub-model
// 0 is left out as a duplicate (its motions would count twice, and its
// misregistered images would make the clean model look contradicted), so
// the first mapper run is accepted and calibrated.
TEST_F(Robustness, DuplicateSubModelIsLeftOut) {
  constexpr int kImages = 30;
  const SimulatedDrive drive = WriteImageFolder(kImages, "x");
  WriteMapperModel(drive, kImages, "seed_0/0", {22, 25}, /*first=*/20);
  WriteMapperModel(drive, kImages, "seed_0/1");
  const std::string bin = WriteFakeColmapWithMapperModels();
  const CommandResult run = RunOdomcal(RunCommand({"--matcher", "sequential"}),
                                       {{"PATH=" + bin + ":/usr/bin:/bin"}});
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const json result = json::parse(ReadFile(Path("ws/calibration.json")));
  EXPECT_EQ(result["status"], "success");
  const json& colmap = result["colmap"];
  ASSERT_EQ(colmap["sub_models"].size(), 1u) << colmap.dump(2);
  EXPECT_EQ(colmap["sub_models"][0]["name"], "1");
  ASSERT_EQ(colmap["duplicate_sub_models"].size(), 1u) << colmap.dump(2);
  EXPECT_EQ(colmap["duplicate_sub_models"][0]["name"], "0");
  EXPECT_EQ(colmap["duplicate_sub_models"][0]["duplicate_of"], "1");
  EXPECT_EQ(colmap["duplicate_sub_models"][0]["num_registered_images"], 10);
  ASSERT_EQ(colmap["mapper_attempts"].size(), 1u) << colmap.dump(2);
  EXPECT_EQ(colmap["mapper_attempts"][0]["num_contradicting_pairs"], 0);
  EXPECT_TRUE(ContainsName(
      result["warnings"],
      "sub-model 0 (10 images) holds no image that sub-model 1 does "
      "not: left out as a second reconstruction of the same images"))
      << result["warnings"].dump(2);
  EXPECT_TRUE(fs::exists(dir_ / "ws" / "sparse_metric" / "1"));
  EXPECT_FALSE(fs::exists(dir_ / "ws" / "sparse_metric" / "0"));
}

// Every run contradicted elsewhere: the least contradicted model is
// calibrated, with a warning (here without matching again). Contradicted
// where the previous run was: the mapping stops (another seed changed
// nothing); new matches contradicted there too end it (the odometry or the
// images are at fault). --mapper_attempts 1 maps once.
TEST_F(Robustness, MapperModelsAllContradictedAreReported) {
  constexpr int kImages = 30;
  const SimulatedDrive drive = WriteImageFolder(kImages, "x");
  WriteMapperModel(drive, kImages, "seed_0", {7, 19});
  WriteMapperModel(drive, kImages, "seed_1", {12});
  WriteMapperModel(drive, kImages, "seed_2", {4, 15, 23});
  const std::string bin = WriteFakeColmapWithMapperModels();
  const auto run_in_fresh_workspace =
      [&](const std::vector<std::string>& extra) {
        fs::remove_all(dir_ / "ws");
        std::vector<std::string> flags = {"--matcher", "sequential"};
        flags.insert(flags.end(), extra.begin(), extra.end());
        const CommandResult run =
            RunOdomcal(RunCommand(flags), {{"PATH=" + bin + ":/usr/bin:/bin"}});
        EXPECT_EQ(run.exit_code, 0) << run.out << run.err;
        return json::parse(ReadFile(Path("ws/calibration.json")));
      };
  json result = run_in_fresh_workspace({"--rematch", "off"});
  json attempts = result["colmap"]["mapper_attempts"];
  ASSERT_EQ(attempts.size(), 3u);
  EXPECT_TRUE(attempts[1]["chosen"]) << attempts.dump(2);
  EXPECT_LT(attempts[1]["num_contradicting_pairs"],
            attempts[0]["num_contradicting_pairs"]);
  EXPECT_TRUE(
      ContainsName(result["warnings"],
                   "every one of 3 COLMAP mapper runs gave motion pairs that "
                   "contradict the odometry; the model of --random_seed 1 "
                   "contradicts it least"))
      << result["warnings"].dump(2);
  EXPECT_FALSE(fs::exists(dir_ / "ws" / "database_rematched.db"));

  WriteMapperModel(drive, kImages, "seed_1", {7, 19});
  result = run_in_fresh_workspace({"--rematch", "off"});
  attempts = result["colmap"]["mapper_attempts"];
  ASSERT_EQ(attempts.size(), 2u) << attempts.dump(2);
  EXPECT_TRUE(attempts[0]["chosen"]);
  EXPECT_EQ(attempts[1]["num_pairs_left_out"], 0);
  EXPECT_TRUE(ContainsName(
      result["warnings"],
      "COLMAP mapper runs with --random_seed 0 and 1 gave the same " +
          attempts[1]["num_contradicting_pairs"].dump() +
          " motion pairs that contradict the odometry: the odometry or the "
          "images "
          "disagree there, not COLMAP's randomness"))
      << result["warnings"].dump(2);
  EXPECT_FALSE(fs::exists(dir_ / "ws" / "database_rematched.db"));

  // The new matches contradicted at the same pairs again: no second seed.
  WriteMapperModel(drive, kImages, "rematch_seed_0", {7, 19});
  WriteMapperModel(drive, kImages, "rematch_seed_1");
  result = run_in_fresh_workspace({});
  attempts = result["colmap"]["mapper_attempts"];
  ASSERT_EQ(attempts.size(), 3u) << attempts.dump(2);
  EXPECT_TRUE(attempts[0]["chosen"]);
  EXPECT_EQ(attempts[2]["matching_round"], 1);
  EXPECT_TRUE(ContainsName(result["warnings"],
                           "COLMAP mapper runs on two matchings (--random_seed "
                           "0, --random_seed 0 on the new "
                           "matches) gave the same " +
                               attempts[2]["num_contradicting_pairs"].dump() +
                               " motion pairs that contradict the odometry: "
                               "the odometry or the images "
                               "disagree there, not COLMAP's randomness"))
      << result["warnings"].dump(2);

  result =
      run_in_fresh_workspace({"--mapper_attempts", "1", "--rematch", "off"});
  EXPECT_EQ(result["colmap"]["mapper_attempts"].size(), 1u);
}

// The stage markers record a stage's arguments, not the lists its arguments
// name: a rerun on the same workspace with other frames (a changed
// image_list.txt) must run the stages anew, not reuse the old features and
// models; a rerun with the same frames reuses every stage.
TEST_F(Robustness, RerunWithOtherFramesRunsTheStagesAnew) {
  constexpr int kImages = 30;
  const SimulatedDrive drive = WriteImageFolder(kImages, "x");
  WriteMapperModel(drive, kImages, "seed_0");
  const std::string bin = WriteFakeColmapWithMapperModels();
  const RunLimits environment = {{"PATH=" + bin + ":/usr/bin:/bin"}};
  const std::vector<std::string> flags = {"--matcher", "sequential"};
  CommandResult run = RunOdomcal(RunCommand(flags), environment);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const std::string first_list = ReadFile(dir_ / "ws" / "image_list.txt");

  run = RunOdomcal(RunCommand(flags), environment);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_EQ(run.out.find("... done"), std::string::npos) << run.out;

  std::vector<std::string> spaced = flags;
  spaced.insert(spaced.end(), {"--frame_min_translation_m", "0.3"});
  run = RunOdomcal(RunCommand(spaced), environment);
  EXPECT_NE(ReadFile(dir_ / "ws" / "image_list.txt"), first_list);
  EXPECT_NE(run.out.find("COLMAP feature extraction ... done"),
            std::string::npos)
      << run.out;
  EXPECT_EQ(run.out.find("reused from an earlier run"), std::string::npos)
      << run.out;
}

// The seeds give three models contradicted each elsewhere: odomcal matches
// again, into database_rematched.db (a copy, cleaned of matches, so that
// database.db keeps the first matches), and maps that. Rerun on the same
// workspace, every stage is reused. When the new matches are contradicted too,
// the least contradicted model of either matching is calibrated, with a warning
// naming both.
TEST_F(Robustness, MatchesAgainWhenTheSeedsDoNotHelp) {
  constexpr int kImages = 30;
  const SimulatedDrive drive = WriteImageFolder(kImages, "x");
  WriteMapperModel(drive, kImages, "seed_0", {7, 19});
  WriteMapperModel(drive, kImages, "seed_1", {12, 20});
  WriteMapperModel(drive, kImages, "seed_2", {4, 15, 23});
  WriteMapperModel(drive, kImages, "rematch_seed_0", {5, 25});
  WriteMapperModel(drive, kImages, "rematch_seed_1");
  const std::string bin = WriteFakeColmapWithMapperModels();
  const RunLimits environment = {{"PATH=" + bin + ":/usr/bin:/bin"}};
  CommandResult run =
      RunOdomcal(RunCommand({"--matcher", "sequential"}), environment);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(
      run.out.find(
          "COLMAP sequential matching again, into a copy of the features ... "
          "done"),
      std::string::npos)
      << run.out;
  EXPECT_NE(
      run.out.find("COLMAP mapping the new matches, --random_seed 1 ... done"),
      std::string::npos)
      << run.out;
  json result = json::parse(ReadFile(Path("ws/calibration.json")));
  EXPECT_EQ(result["status"], "success");
  json attempts = result["colmap"]["mapper_attempts"];
  ASSERT_EQ(attempts.size(), 5u) << attempts.dump(2);
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(attempts[i]["matching_round"], i < 3 ? 0 : 1) << attempts.dump(2);
    EXPECT_EQ(attempts[i]["chosen"], i == 4) << attempts.dump(2);
  }
  EXPECT_EQ(attempts[4]["path"], Path("ws/mapper_attempts/rematch_seed_1"));
  EXPECT_EQ(attempts[4]["num_contradicting_pairs"], 0);
  EXPECT_EQ(ReadFile(dir_ / "ws" / "sparse" / "0" / "images.bin"),
            ReadFile(dir_ / "models" / "rematch_seed_1" / "images.bin"));
  EXPECT_TRUE(result["warnings"].empty()) << result["warnings"].dump(2);
  const std::string commands = ReadFile(dir_ / "ws" / "commands.txt");
  EXPECT_NE(commands.find("database_cleaner --type matches --database_path " +
                          Path("ws/database_rematched.db")),
            std::string::npos)
      << commands;
  EXPECT_NE(commands.find("sequential_matcher --database_path " +
                          Path("ws/database_rematched.db")),
            std::string::npos)
      << commands;
  EXPECT_NE(commands.find("mapper --database_path " +
                          Path("ws/database_rematched.db")),
            std::string::npos)
      << commands;
  EXPECT_TRUE(fs::exists(dir_ / "ws" / "database.db"));

  run = RunOdomcal(RunCommand({"--matcher", "sequential"}), environment);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_EQ(run.out.find("... done"), std::string::npos) << run.out;
  EXPECT_EQ(ReadFile(dir_ / "ws" / "commands.txt"), commands);

  WriteMapperModel(drive, kImages, "rematch_seed_1", {kImages - 1});  // 1 pair
  fs::remove_all(dir_ / "models" / "rematch_seed_2");
  fs::remove_all(dir_ / "ws");
  run = RunOdomcal(RunCommand({"--matcher", "sequential"}), environment);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  result = json::parse(ReadFile(Path("ws/calibration.json")));
  attempts = result["colmap"]["mapper_attempts"];
  ASSERT_EQ(attempts.size(), 6u) << attempts.dump(2);
  EXPECT_TRUE(attempts[4]["chosen"]) << attempts.dump(2);
  EXPECT_TRUE(ContainsName(
      result["warnings"],
      "every one of 6 COLMAP mapper runs on two matchings gave motion "
      "pairs that contradict the odometry; the model of --random_seed 1 "
      "on the new matches contradicts it least"))
      << result["warnings"].dump(2);
  // The misregistered last image is in no pair the odometry confirms: it is
  // left out of the metric model.
  EXPECT_TRUE(ContainsName(
      result["warnings"],
      "sparse_metric/0: left out 1 image whose every motion pair the "
      "odometry contradicts (" +
          ImageName(kImages - 1) + ")"))
      << result["warnings"].dump(2);
  const ColmapModel metric = ReadColmapModel(Path("ws/sparse_metric/0"));
  EXPECT_EQ(metric.images.size(), static_cast<size_t>(kImages - 1));
  for (const auto& [id, image] : metric.images)
    EXPECT_NE(image.name, ImageName(kImages - 1));
}

// Real COLMAP on files that are not images: feature_extractor skips every
// one and exits 0. Skipped without colmap on PATH.
TEST_F(Robustness, UnreadableImagesWithRealColmap) {
  if (std::system("colmap help > /dev/null 2>&1") != 0) {
    GTEST_SKIP() << "colmap is not installed";
  }
  WriteImageFolder(5, "this is not a PNG file\n");
  const CommandResult run = RunOdomcal(RunCommand());
  ExpectColmapFailure(
      run,
      std::string(kRunError) + "COLMAP could read none of the 5 images in " +
          Path("images") + " (see " + Path("ws/logs/feature_extractor.log") +
          ": ERROR: Failed to read image file format.)");
}

// ---------------------------------------------------------------------------
// Outputs.

TEST_F(Robustness, OutputExists) {
  WriteDrive();
  WriteFile(Path("result.json"), "precious");
  ExpectBadInput(RunOdomcal(Calibrate()),
                 std::string(kCalibrateError) + Path("result.json") +
                     ": exists (pass --overwrite to replace it)");
  EXPECT_EQ(ReadFile(Path("result.json")), "precious");

  WriteColmapProject();
  fs::create_directories(Path("out"));
  WriteFile(Path("out/keep.txt"), "precious");
  ExpectBadInput(
      RunOdomcal(Colmap()),
      std::string(kColmapError) + Path("out") +
          ": is not empty (pass --overwrite to replace odomcal's files in it)");
  EXPECT_EQ(ReadFile(Path("out/keep.txt")), "precious");
}

// Permissions do not stop root, so the unwritable places are ones no user
// can write: a path below a regular file, and /proc.
TEST_F(Robustness, OutputNotWritable) {
  WriteDrive();
  WriteFile(Path("a_file"), "");
  ExpectBadInput(RunOdomcal(Calibrate("a_file/result.json")),
                 std::string(kCalibrateError) + Path("a_file/result.json") +
                     ": " + Path("a_file") + " is not a folder");
  std::vector<std::string> arguments = Calibrate();
  arguments.back() = "/proc/odomcal_result.json";
  ExpectBadInputContaining(
      RunOdomcal(arguments),
      std::string(kCalibrateError) +
          "/proc/odomcal_result.json: cannot create a temporary file (",
      {});

  WriteColmapProject();
  ExpectBadInput(RunOdomcal(Colmap("a_file/out")),
                 std::string(kColmapError) + Path("a_file/out") +
                     ": cannot create (Not a directory)");
}

TEST_F(Robustness, OutputInsideTheInputProject) {
  WriteColmapProject();
  const std::string inside =
      (dir_ / "project" / "sparse" / "0" / "out").string();
  ExpectBadInput(RunOdomcal(Colmap("project/sparse/0/out")),
                 std::string(kColmapError) + inside +
                     " (--output_path) is inside the input folder " +
                     (dir_ / "project" / "sparse").string() +
                     " (--model_path); odomcal never writes into an input");
  EXPECT_FALSE(fs::exists(inside));
}

// A full disk, simulated by limiting the size of files odomcal may write to
// 1 KiB: the result JSON is larger, write() fails with EFBIG.
TEST_F(Robustness, DiskFullDuringWrite) {
  WriteDrive();
  RunLimits limits;
  limits.max_file_size_bytes = 1024;
  ExpectBadInput(RunOdomcal(Calibrate(), limits),
                 std::string(kCalibrateError) + Path("result.json") +
                     ": write failed (File too large)");
  for (const auto& entry : fs::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().filename().string().find("result"),
              std::string::npos)
        << "left behind: " << entry.path();
  }

  WriteColmapProject();
  ExpectBadInputContaining(
      RunOdomcal(Colmap(), limits), kColmapError, {"File too large"});
  EXPECT_FALSE(fs::exists(Path("out/calibration.json")) &&
               fs::file_size(Path("out/calibration.json")) == 0);
}

}  // namespace
}  // namespace odomcal
