// The fixture of the bad-input tests of the odomcal executable
// (robustness_test.cc, robustness_colmap_test.cc): scratch folders, simulated
// drives and COLMAP projects written as files, fake colmap executables, and
// the command lines of the commands under test.
#pragma once

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

namespace odomcal::robustness_test {

namespace fs = std::filesystem;
using json = nlohmann::json;

inline constexpr char kCalibrateError[] = "odomcal calibrate: error: ";
inline constexpr char kColmapError[] = "odomcal colmap: error: ";
inline constexpr char kRunError[] = "odomcal run: error: ";

// No NaN or Inf written as a number (OpenCV's YAML spells them .nan, .inf).
inline void ExpectNoNonFiniteText(const std::string& text) {
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
inline void ExpectColmapFailure(const CommandResult& run,
                                const std::string& line) {
  EXPECT_EQ(run.exit_code, 4) << run.out << run.err;
  EXPECT_EQ(run.err, line + "\n");
}

// "000042.png": the name of test image `index`.
inline std::string ImageName(size_t index) {
  char name[32];
  std::snprintf(name, sizeof(name), "%06zu.png", index);
  return name;
}

// Image ImageName(index) of camera 1 at `world_from_cam`.
inline ColmapImage MakeColmapImage(uint32_t image_id,
                                   size_t index,
                                   const Rigid3d& world_from_cam) {
  ColmapImage image;
  image.image_id = image_id;
  image.camera_id = 1;
  image.name = ImageName(index);
  image.cam_from_world = Inverse(world_from_cam);
  return image;
}

inline bool ContainsName(const json& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// Replaces line `line_number` (1-based) of the text file at `path`.
inline void ReplaceLine(const fs::path& path,
                        int line_number,
                        const std::string& text) {
  std::istringstream in(ReadFile(path));
  std::string line, result;
  for (int k = 1; std::getline(in, line); ++k) {
    result += (k == line_number ? text : line) + "\n";
  }
  WriteFile(path, result);
}

inline std::string Line(const fs::path& path, int line_number) {
  std::istringstream in(ReadFile(path));
  std::string line;
  for (int k = 1; k <= line_number; ++k) std::getline(in, line);
  return line;
}

// A robot path integrated from its speed (m/s) and yaw rate (rad/s) at time
// t: odometry at 50 Hz, and the camera of the simulator's default mount at
// 10 Hz in an SfM frame of kMetricScale metres per unit. No noise: the two
// files agree exactly, so what a test sees comes from the motion alone.
inline constexpr double kMetricScale = 0.37;
struct PathFiles {
  Trajectory odometry;
  Trajectory camera;
};
inline PathFiles IntegratePath(
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
    return WriteFakeColmap(FakeMapperModelsBody(chunks_side_by_side, adjusts));
  }

  // The stages of WriteFakeColmapWithMapperModels, without the banner.
  std::string FakeMapperModelsBody(bool chunks_side_by_side = false,
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
    return "if [ \"$1\" = feature_extractor ]; then cp " +
           WritePreparedDatabase() +
           " \"$3\"; fi\n"
           "if [ \"$1\" = mapper ]; then\n"
           "  while [ $# -gt 0 ]; do\n"
           "    case \"$1\" in --output_path) out=\"$2\";; --random_seed) "
           "seed=\"$2\";;\n"
           "      --database_path) case \"$2\" in *rematched.db) "
           "round=rematch_;; "
           "esac;; esac\n"
           "    shift\n"
           "  done\n" +
           wait_for_chunk_1 + "  model=" + Path("models") +
           "/${round}seed_$seed\n"
           "  if [ -d \"$model/0\" ]; then cp -r \"$model\"/* \"$out/\";\n"
           "  elif [ -d \"$model\" ]; then mkdir -p \"$out/0\" && cp "
           "\"$model\"/* "
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
           "exit 0\n";
  }

  // bin/colmap of COLMAP `version` ("3.8" or "4.1"): its banner, and every
  // option odomcal passes checked against the names that version's
  // command registers (COLMAP's option_manager.cc and exe/*.cc at the
  // release tag; docs/colmap_versions.md): an unknown one fails as
  // COLMAP fails, "Failed to parse options - unrecognised option" and exit
  // 1. The stages then behave as WriteFakeColmapWithMapperModels' (the
  // mapper's seed from the version's seed option).
  std::string WriteStrictFakeColmap(const std::string& version) const {
    const bool v4 = version == "4.1";
    const std::string extraction = v4 ? "FeatureExtraction" : "SiftExtraction";
    const std::string matching = v4 ? "FeatureMatching" : "SiftMatching";
    const std::string seed =
        v4 ? "default_random_seed Mapper.random_seed" : "random_seed";
    const std::string banner =
        v4 ? "COLMAP 4.1.1 (Commit 0a1b2c3 on 2026-07-17 without CUDA)"
           : "COLMAP 3.8 -- Structure-from-Motion and Multi-View Stereo";
    std::map<std::string, std::string> allowed = {
        {"feature_extractor",
         "database_path image_path image_list_path ImageReader.single_camera "
         "ImageReader.camera_model ImageReader.camera_params " +
             extraction + ".use_gpu " + extraction +
             ".num_threads SiftExtraction.max_num_features"},
        {"sequential_matcher",
         "database_path " + matching + ".use_gpu " + matching +
             ".num_threads SequentialMatching.overlap"},
        {"matches_importer",
         "database_path match_list_path match_type " + matching + ".use_gpu " +
             matching + ".num_threads"},
        {"database_cleaner", "type database_path"},
        {"mapper",
         "database_path image_path output_path input_path " +
             std::string(v4 ? "Mapper.image_list_path " : "image_list_path ") +
             seed +
             " Mapper.num_threads Mapper.ba_refine_focal_length "
             "Mapper.ba_refine_principal_point Mapper.ba_refine_extra_params "
             "Mapper.init_min_tri_angle Mapper.init_max_forward_motion "
             "Mapper.init_image_id1 Mapper.init_image_id2 "
             "Mapper.init_min_num_inliers"},
        {"point_triangulator",
         "database_path image_path input_path output_path clear_points"},
        {"bundle_adjuster",
         "input_path output_path BundleAdjustment.refine_focal_length "
         "BundleAdjustment.refine_principal_point "
         "BundleAdjustment.refine_extra_params"}};
    if (v4) {
      // COLMAP 4.0-4.1 RunGlobalMapper: no Mapper.* and no input_path.
      allowed["global_mapper"] =
          "database_path image_path output_path GlobalMapper.image_list_path "
          "GlobalMapper.num_threads GlobalMapper.random_seed "
          "GlobalMapper.ba_refine_focal_length "
          "GlobalMapper.ba_refine_principal_point "
          "GlobalMapper.ba_refine_extra_params default_random_seed";
    }
    return WriteFakeColmapBanner(
        banner,
        StrictOptionCheck(allowed) +
            FakeMapperBody(
                v4 ? "--default_random_seed|--GlobalMapper.random_seed"
                   : "--random_seed"));
  }

  // bin/glomap: GLOMAP 1.x's banner, `glomap mapper` with the options it
  // registers (glomap/exe/global_mapper.cc and option_manager.cc), mapping
  // as WriteFakeColmapWithMapperModels' mapper with seed 0 (GLOMAP has no
  // seed option).
  void WriteStrictFakeGlomap() const {
    const std::map<std::string, std::string> allowed = {
        {"mapper",
         "database_path image_path output_path constraint_type output_format "
         "BundleAdjustment.optimize_intrinsics "
         "BundleAdjustment.optimize_principal_point"}};
    fs::create_directories(dir_ / "bin");
    const fs::path script = dir_ / "bin" / "glomap";
    WriteFile(script,
              "#!/bin/sh\n"
              "if [ \"$1\" = help ]; then\n"
              "  echo 'GLOMAP -- Global Structure-from-Motion'\n"
              "  exit 0\n"
              "fi\n"
              "seed=0\n" +
                  StrictOptionCheck(allowed) + FakeMapperBody("--random_seed"));
    ::chmod(script.c_str(), 0755);
  }

  // WriteFakeColmapWithMapperModels' stages, `global_mapper` mapping as
  // `mapper` does, the seed read from `seed_options` (a shell pattern).
  std::string FakeMapperBody(const std::string& seed_options) const {
    std::string body = FakeMapperModelsBody();
    const std::string command = "if [ \"$1\" = mapper ]; then";
    body.replace(body.find(command),
                 command.size(),
                 "if [ \"$1\" = mapper ] || [ \"$1\" = global_mapper ]; then");
    const std::string from = "--random_seed) ";
    body.replace(body.find(from), from.size(), seed_options + ") ");
    return body;
  }

  // A shell fragment that exits 1 as COLMAP does on a command or an option
  // name `allowed` does not list for the command.
  static std::string StrictOptionCheck(
      const std::map<std::string, std::string>& allowed) {
    std::string check = "case \"$1\" in\n";
    for (const auto& [command, names] : allowed) {
      check += "  " + command + ") allowed=' " + names + " ';;\n";
    }
    check +=
        "  *) echo \"unknown command $1\" >&2; exit 1;;\n"
        "esac\n"
        "for argument in \"$@\"; do\n"
        "  case \"$argument\" in --*)\n"
        "    case \"$allowed\" in *\" ${argument#--} \"*) ;;\n"
        "      *) echo \"ERROR: Failed to parse options - unrecognised option "
        "'$argument'.\" >&2; exit 1;;\n"
        "    esac;;\n"
        "  esac\n"
        "done\n";
    return check;
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
    return WriteFakeColmapBanner(
        "COLMAP 3.8 -- Structure-from-Motion and Multi-View Stereo", body);
  }

  // bin/colmap printing `banner` for `colmap help`, else running `body`.
  std::string WriteFakeColmapBanner(const std::string& banner,
                                    const std::string& body) const {
    fs::create_directories(dir_ / "bin");
    const fs::path script = dir_ / "bin" / "colmap";
    WriteFile(script,
              "#!/bin/sh\n"
              "if [ \"$1\" = help ]; then\n"
              "  echo '" +
                  banner +
                  "'\n"
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
    if (fs::exists(path)) return path;  // written by an earlier fake
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

}  // namespace odomcal::robustness_test
