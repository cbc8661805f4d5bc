// End-to-end regression through COLMAP: `odomcal render` a preset, `odomcal
// run` on it (COLMAP 3.8 on the CPU, then the calibration), and compare with
// the rendered ground truth. Skipped when COLMAP is not installed.
//
// Tolerances (issue #5): rotation 0.1 deg, x/y 5 mm, metric model scale
// 0.3 % for the clean presets; see the `hard` test for its own. Seed 1 by
// default; ODOMCAL_TEST_SEED renders other scenes (the tolerances must hold).

#include "odomcal/adapters/colmap_model.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/format_number.h"
#include "odomcal/solver/rigid3.h"
#include "odomcal/tests/test_files.h"
#include "odomcal/tests/test_seed.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>

namespace odomcal {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

bool ColmapInstalled() {
  return std::system("colmap help > /dev/null 2>&1") == 0;
}

struct PresetRun {
  int exit_code = -1;
  std::string log;
  json result;
  json truth;
  fs::path workspace;
  bool inputs_unchanged = false;  // images, odometry, timestamps
  double run_seconds = 0.0;       // of `odomcal run` alone
};

class RenderedEndToEnd : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!ColmapInstalled()) GTEST_SKIP() << "colmap is not installed";
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ =
        fs::path(::testing::TempDir()) / (std::string("e2e_") + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (std::getenv("ODOMCAL_KEEP_TEST_FILES") == nullptr) fs::remove_all(dir_);
  }

  int Run(const std::string& arguments, std::string* log) const {
    const fs::path out = dir_ / "log.txt";
    const std::string command = std::string(ODOMCAL_EXECUTABLE) + " " +
                                arguments + " > " + out.string() + " 2>&1";
    const int status = std::system(command.c_str());
    *log += ReadFile(out);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  // Renders `preset` and runs the whole pipeline with the true intrinsics;
  // z comes from the floor (the rendered odometry frame lies on it).
  PresetRun RunPreset(const std::string& preset,
                      uint64_t seed,
                      const std::string& extra_run_flags = "") const {
    PresetRun run;
    const fs::path data = dir_ / "data";
    run.workspace = dir_ / "ws";
    const std::string seed_text = std::to_string(seed);
    if (Run("render --preset " + preset + " --seed " + seed_text +
                " --output_path " + data.string(),
            &run.log) != 0) {
      return run;
    }
    run.truth = json::parse(ReadFile(data / "ground_truth.json"));
    std::string params;
    for (const auto& value : run.truth["camera"]["params"]) {
      std::ostringstream text;
      text.precision(17);
      text << value.get<double>();
      params += (params.empty() ? "" : ",") + text.str();
    }
    const auto inputs_before = Snapshot(data);
    const auto start = std::chrono::steady_clock::now();
    run.exit_code =
        Run("run --image_path " + (data / "images").string() + " --odometry " +
                (data / "odometry.csv").string() + " --image_timestamps " +
                (data / "image_timestamps.csv").string() + " --camera_model " +
                run.truth["camera"]["model"].get<std::string>() +
                " --camera_params " + params + " --workspace_path " +
                run.workspace.string() + " " + extra_run_flags,
            &run.log);
    run.run_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
            .count();
    run.inputs_unchanged = Snapshot(data) == inputs_before;
    if (fs::exists(run.workspace / "calibration.json")) {
      run.result = json::parse(ReadFile(run.workspace / "calibration.json"));
    }
    return run;
  }

  static double RotationErrorDeg(const PresetRun& run) {
    const auto& q = run.result["odom_from_cam"]["quaternion_wxyz"];
    const auto& t = run.truth["odom_from_cam"]["quaternion_wxyz"];
    const Eigen::Quaterniond estimate(q[0], q[1], q[2], q[3]);
    const Eigen::Quaterniond truth(t[0], t[1], t[2], t[3]);
    return RotationAngle(estimate.conjugate() * truth) * kRadToDeg;
  }

  static Eigen::Vector2d TranslationErrorM(const PresetRun& run) {
    const auto& e = run.result["odom_from_cam"]["translation_m"];
    const auto& t = run.truth["odom_from_cam"]["translation_m"];
    return Eigen::Vector2d(e[0].get<double>() - t[0].get<double>(),
                           e[1].get<double>() - t[1].get<double>());
  }

  // Relative size of the exported metric models against the true camera
  // positions (pairwise distances within each model): 0 when exact.
  static std::vector<double> MetricModelScaleErrors(const PresetRun& run) {
    std::map<std::string, Eigen::Vector3d> truth;
    for (const auto& image : run.truth["images"]) {
      const auto& t = image["world_from_cam"]["translation_m"];
      truth[image["name"].get<std::string>()] =
          Eigen::Vector3d(t[0], t[1], t[2]);
    }
    std::vector<double> errors;
    for (const auto& entry :
         fs::directory_iterator(run.workspace / "sparse_metric")) {
      const ColmapModel model = ReadColmapModel(entry.path().string());
      std::vector<Eigen::Vector3d> estimated, expected;
      for (const auto& [id, image] : model.images) {
        estimated.push_back(Inverse(image.cam_from_world).translation);
        expected.push_back(truth.at(image.name));
      }
      double numerator = 0.0, denominator = 0.0;
      for (size_t i = 0; i < expected.size(); ++i) {
        for (size_t j = i + 1; j < expected.size(); ++j) {
          const double d = (expected[i] - expected[j]).norm();
          numerator += (estimated[i] - estimated[j]).norm() * d;
          denominator += d * d;
        }
      }
      errors.push_back(numerator / denominator - 1.0);
    }
    return errors;
  }

  void ExpectAccurate(const PresetRun& run,
                      double rotation_deg,
                      double translation_m,
                      double scale_rel,
                      double min_fraction_in_calibration = 0.9) const {
    ASSERT_EQ(run.exit_code, 0) << run.log;
    EXPECT_TRUE(run.inputs_unchanged) << "odomcal run modified its inputs";
    EXPECT_EQ(run.result["status"], "success") << run.log;
    EXPECT_LT(RotationErrorDeg(run), rotation_deg) << run.log;
    const Eigen::Vector2d t = TranslationErrorM(run);
    // The measured errors, for the record (seed spread in the notes).
    std::cout << "[ errors   ] rotation " << RotationErrorDeg(run) << " deg, x "
              << 1000.0 * t.x() << " mm, y " << 1000.0 * t.y() << " mm, scale";
    for (const double error : MetricModelScaleErrors(run)) {
      std::cout << " " << 100.0 * error << " %";
    }
    // "14 10 2 | 0*": a run per seed, '|' before those on new matches.
    std::cout << "; contradicting pairs per mapper run:";
    int round = 0;
    for (const auto& attempt : run.result["colmap"]["mapper_attempts"]) {
      if (attempt["matching_round"] != round) std::cout << " |";
      round = attempt["matching_round"];
      std::cout << " " << attempt["num_contradicting_pairs"]
                << (attempt["chosen"] ? "*" : "");
    }
    std::cout << std::endl;
    EXPECT_LT(std::abs(t.x()), translation_m) << run.log;
    EXPECT_LT(std::abs(t.y()), translation_m) << run.log;
    ExpectCameraHeightFromTheFloor(run);
    for (const double error : MetricModelScaleErrors(run)) {
      EXPECT_LT(std::abs(error), scale_rel) << run.log;
    }
    // A scene's drive is meant to be calibrated whole (but for what it
    // cannot show, e.g. a featureless corridor): a model that leaves images
    // out is a regression of the matching or mapping even when the rest
    // calibrates accurately.
    const json& coverage = run.result["colmap"]["image_coverage"];
    std::cout << "[ coverage ] " << coverage["num_in_calibration"] << " of "
              << coverage["num_selected_images"] << " selected images"
              << std::endl;
    EXPECT_GE(coverage["num_in_calibration"].get<double>(),
              min_fraction_in_calibration *
                  coverage["num_selected_images"].get<double>())
        << run.log;
  }

  // Issue 40: z from the floor plane within 5 mm of the truth and within
  // its stated 3 sigma; the floor's roll and pitch within 0.2 deg of the
  // true mount's, measured as the angle between the odometry's up seen from
  // the camera under the floor's rotation, Exp(phi) * R, and under the truth
  // (roll and pitch without the Euler angles' singularity: `tilted` is
  // pitched 80 deg in them).
  static void ExpectCameraHeightFromTheFloor(const PresetRun& run) {
    ASSERT_EQ(run.result["translation_z_source"], "floor_plane") << run.log;
    const double z = run.result["odom_from_cam"]["translation_m"][2];
    const double z_true = run.truth["odom_from_cam"]["translation_m"][2];
    const double sigma = run.result["stddev"]["translation_z_m"];
    const auto& q = run.result["odom_from_cam"]["quaternion_wxyz"];
    const auto& t = run.truth["odom_from_cam"]["quaternion_wxyz"];
    const auto& phi = run.result["floor_plane"]["roll_pitch_correction_deg"];
    const Eigen::Quaterniond floor_rotation =
        ExpRotation(Eigen::Vector3d(phi[0].get<double>() * kDegToRad,
                                    phi[1].get<double>() * kDegToRad,
                                    0.0)) *
        Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized();
    const Eigen::Quaterniond truth(t[0], t[1], t[2], t[3]);
    const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
    const double tilt_error_deg =
        std::acos(std::clamp(
            (floor_rotation.conjugate() * up).dot(truth.conjugate() * up),
            -1.0,
            1.0)) *
        kRadToDeg;
    std::cout << "[ floor    ] z " << 1000.0 * (z - z_true) << " mm (3 sigma "
              << 3000.0 * sigma << " mm), floor roll/pitch error "
              << tilt_error_deg << " deg" << std::endl;
    EXPECT_LT(std::abs(z - z_true), 0.005) << run.log;
    EXPECT_LE(std::abs(z - z_true), 3.0 * sigma) << run.log;
    EXPECT_LT(tilt_error_deg, 0.2) << run.log;
    // A check that agreed leaves the two-step estimate and fits the floor on
    // the adjustment's model too: the two heights' difference is in z's
    // sigma.
    const json& joint = run.result["joint_adjustment"];
    const json& difference =
        run.result["floor_plane"]["camera_height_model_difference_m"];
    if (joint.is_object() && joint["status"] == "success" &&
        joint["use"] == "check" && !joint["adopted"].get<bool>()) {
      ASSERT_TRUE(difference.is_number()) << run.log;
      std::cout << "[ floor    ] the adjustment's model's camera height "
                << 1000.0 * difference.get<double>() << " mm off" << std::endl;
      EXPECT_GE(sigma, std::abs(difference.get<double>())) << run.log;
    } else {
      EXPECT_TRUE(difference.is_null()) << run.log;
    }
  }

  fs::path dir_;
};

// Two rooms joined by a featureless corridor: COLMAP returns two sub-models,
// calibrated as two segments with their own scales. The odometry has 1.5 % /
// 1.0 % wheel-scale errors, 1 % slip and a 0.01 rad/s yaw-rate bias; the
// camera clock a 25 ms offset (not given to odomcal) with 2 ms jitter.
// odomcal estimates the clock offset, the yaw scale, yaw per metre and the
// yaw-rate bias with the extrinsic (docs/systematics.md), which removes the
// odometry's heading errors that the extrinsic's yaw used to absorb (0.22-0.37
// deg before). Tolerances, from the errors measured on seeds 1-3 with the
// frames 5 cm / 3 deg apart, the default then (rotation 0.015, 0.002, 0.031
// deg; x/y up to 2.3, 1.5, 3.0 mm; model scales up to 0.26, 0.23, 0.49 %;
// offset 0.1-0.5 ms off; seed 1 with the frames spaced for triangulation:
// 0.006 deg, 2.7 mm, 0.19 %), with a margin for COLMAP's run-to-run
// variation:
// - rotation 0.1 deg, x/y 6 mm;
// - metric model scale 1 % per exported model: the odometry's own distance
//   error along a stretch (mean wheel-scale error +0.25 %, slip), which no
//   monocular calibration can separate from the scale, is inherited;
// - clock offset within 5 ms of the truth (the negative of the camera's
//   lateness).
// The corridor defeats the spatial matcher's 8 neighbours at 2048 features
// (one room only); sequential matching with 4096 features reconstructs both,
// with an overlap of 5 (not 10) to halve the matching. With the frames 5 cm /
// 3 deg apart (fixed spacing) its slip contradicted the same
// few pairs on every model, so odomcal matched twice; spaced for
// triangulation (the default now: 102 selected images) the first model is
// accepted (seed 1; 94 s instead of 154 s). The second matching is tested
// with a scripted COLMAP (Robustness.MatchesAgainWhenTheSeedsDoNotHelp). One
// model (--chunk_images 0): the scene, not the chunking, is tested here.
// Defined first, being the longest: ctest -j starts tests in the order
// listed, so `hard` runs beside the others instead of after them.
TEST_F(RenderedEndToEnd, HardPresetSplitsIntoTwoSegments) {
  const PresetRun run = RunPreset(
      "hard",
      TestSeed(1),
      "--matcher sequential --max_num_features 4096 --sequential_overlap 5 "
      "--mapper_attempts 1 --chunk_images 0");
  // The featureless corridor's images (about a fifth) cannot be registered:
  // 77 of 102 selected images in the calibration on seed 1; a room lost
  // would leave less than half.
  ExpectAccurate(run, 0.1, 0.006, 0.01, 0.6);
  ASSERT_TRUE(run.result.contains("camera_time_offset_s")) << run.log;
  const double true_offset_s =
      -run.truth["timing"]["camera_time_offset_s"].get<double>();
  EXPECT_NEAR(
      run.result["camera_time_offset_s"].get<double>(), true_offset_s, 0.005)
      << run.log;
  EXPECT_GE(run.result["metric_scales"].size(), 2u) << run.log;
  EXPECT_GE(run.result["colmap"]["sub_models"].size(), 2u) << run.log;
}

TEST_F(RenderedEndToEnd, SmallPreset) {
  const PresetRun run = RunPreset("small", TestSeed(1));
  ExpectAccurate(run, 0.1, 0.005, 0.003);
  // `odomcal colmap` on the project `odomcal run` made gives the same answer.
  std::string log;
  const fs::path data = dir_ / "data";
  const auto project_before = Snapshot(run.workspace);
  const std::string colmap =
      "colmap --model_path " + (run.workspace / "sparse").string() +
      " --database_path " + (run.workspace / "database.db").string() +
      " --odometry " + (data / "odometry.csv").string() +
      " --image_timestamps " + (data / "image_timestamps.csv").string();
  ASSERT_EQ(
      Run(colmap + " --output_path " + (dir_ / "colmap_out").string(), &log), 0)
      << log;
  EXPECT_TRUE(Snapshot(run.workspace) == project_before)
      << "odomcal colmap modified its input";
  const json again =
      json::parse(ReadFile(dir_ / "colmap_out" / "calibration.json"));
  EXPECT_EQ(again["odom_from_cam"]["quaternion_wxyz"],
            run.result["odom_from_cam"]["quaternion_wxyz"]);
  EXPECT_EQ(again["odom_from_cam"]["translation_m"],
            run.result["odom_from_cam"]["translation_m"]);
  EXPECT_EQ(again["metric_scales"], run.result["metric_scales"]);
  // A given z overrides the floor's, which is then only checked.
  ASSERT_EQ(Run(colmap + " --fixed_translation_z_m 0.4 --output_path " +
                    (dir_ / "colmap_given_z").string(),
                &log),
            0)
      << log;
  const json given =
      json::parse(ReadFile(dir_ / "colmap_given_z" / "calibration.json"));
  EXPECT_EQ(given["odom_from_cam"]["translation_m"][2], 0.4);
  EXPECT_EQ(given["translation_z_source"], "given");
  EXPECT_EQ(given["options"]["floor_plane"], "check");
  EXPECT_EQ(given["floor_plane"]["used_for_translation_z"], false);
  EXPECT_NEAR(given["floor_plane"]["camera_height_m"].get<double>(),
              run.result["floor_plane"]["camera_height_m"].get<double>(),
              1e-4);
}

// Camera pitched 10 deg down and rolled 90 deg: roll and pitch of the
// extrinsic far from the forward mount, same tolerances. The rendered drive
// reaches odomcal as a robot records it: a ROS 1 bag written by Debian's
// python3-rosbag (tests/fixtures/bags/rendered_to_ros1_bag.py: PNG
// CompressedImage, CameraInfo in ROS's pixel convention, nav_msgs/Odometry,
// header stamps the capture times, received 1-4 ms later), read with
// `run --bag` (intrinsics from CameraInfo). COLMAP is driven through the
// command line of COLMAP 4.1.1 with --mapper global: tests/fake_colmap/
// fake_colmap.py accepts only 4.1.1's option names (global_mapper's
// GlobalMapper.*, FeatureExtraction.*, ...) and runs the installed COLMAP
// 3.8 with them translated (the mapping itself stays 3.8's incremental
// mapper).
TEST_F(RenderedEndToEnd, TiltedCameraFromARos1BagThroughColmap4GlobalMapper) {
  PresetRun run;
  const fs::path data = dir_ / "data";
  const fs::path bag = dir_ / "bag" / "drive.bag";
  fs::create_directories(bag.parent_path());
  run.workspace = dir_ / "ws";
  ASSERT_EQ(Run("render --preset tilted --seed " + std::to_string(TestSeed(1)) +
                    " --output_path " + data.string(),
                &run.log),
            0)
      << run.log;
  run.truth = json::parse(ReadFile(data / "ground_truth.json"));
  ASSERT_EQ(std::system(("/usr/bin/python3 " ODOMCAL_BAG_FROM_RENDERING " " +
                         data.string() + " " + bag.string())
                            .c_str()),
            0);
  const fs::path colmap = dir_ / "colmap_4.1.1";
  {
    std::ofstream wrapper(colmap);
    wrapper << "#!/bin/sh\nexec /usr/bin/python3 " << ODOMCAL_FAKE_COLMAP
            << " --emulate 4.1.1 --real colmap \"$@\"\n";
  }
  fs::permissions(colmap, fs::perms::owner_all, fs::perm_options::add);
  const auto bag_before = Snapshot(bag.parent_path());
  run.exit_code = Run("run --bag " + bag.string() + " --workspace_path " +
                          run.workspace.string() +
                          " --mapper global --colmap_path " + colmap.string(),
                      &run.log);
  run.inputs_unchanged = Snapshot(bag.parent_path()) == bag_before;
  ASSERT_TRUE(fs::exists(run.workspace / "calibration.json")) << run.log;
  run.result = json::parse(ReadFile(run.workspace / "calibration.json"));
  // The extraction names each image by its stamp in ns: the truth's names
  // follow (the rendered times are exact decimals of 0.1 s).
  std::map<std::string, std::string> bag_names;
  std::istringstream times(ReadFile(data / "image_timestamps.csv"));
  std::string line;
  std::getline(times, line);  // header
  while (std::getline(times, line)) {
    const size_t comma = line.find(',');
    const std::string seconds = line.substr(comma + 1);
    const size_t point = seconds.find('.');
    const std::string nanoseconds =
        seconds.substr(0, point) +
        (seconds.substr(point + 1) + "000000000").substr(0, 9);
    bag_names[line.substr(0, comma)] = nanoseconds + ".png";
  }
  for (auto& image : run.truth["images"]) {
    image["name"] = bag_names.at(image["name"].get<std::string>());
  }
  ExpectAccurate(run, 0.1, 0.005, 0.003);
  EXPECT_EQ(run.result["colmap"]["version"], "4.1.1") << run.log;
  EXPECT_EQ(run.result["colmap"]["mapper"], "global_mapper") << run.log;
  EXPECT_EQ(run.result["inputs"]["bag"], bag.string());
  EXPECT_EQ(run.result["options"]["bag"]["bag_time"], "header");
  // The intrinsics came from CameraInfo, moved to COLMAP's pixel centre.
  const std::string camera =
      ReadFile(run.workspace / "bag_inputs" / "camera.txt");
  EXPECT_NE(camera.find("\n1 PINHOLE "), std::string::npos) << camera;
}

TEST_F(RenderedEndToEnd, StraightDrivingIsUnobservable) {
  const PresetRun run = RunPreset("straight", TestSeed(1));
  EXPECT_EQ(run.exit_code, 3) << run.log;
  ASSERT_TRUE(run.result.is_object()) << run.log;
  EXPECT_EQ(run.result["status"], "unobservable");
  EXPECT_EQ(
      run.result["unobservable"],
      json::array(
          {"rotation", "translation_x", "translation_y", "translation_z"}));
  // The odometry alone shows it: refused within seconds, before any COLMAP
  // stage (no database, no command run, no mapper).
  EXPECT_LT(run.run_seconds, 60.0) << run.log;
  EXPECT_FALSE(fs::exists(run.workspace / "database.db")) << run.log;
  EXPECT_FALSE(fs::exists(run.workspace / "commands.txt")) << run.log;
  EXPECT_TRUE(run.result["colmap"]["mapper_attempts"].empty()) << run.log;
}

}  // namespace
}  // namespace odomcal

namespace odomcal {
namespace {

Rigid3d TransformOf(const json& transform) {
  const json& q = transform["quaternion_wxyz"];
  const json& t = transform["translation_m"];
  return Rigid3d(
      Eigen::Quaterniond(q[0].get<double>(),
                         q[1].get<double>(),
                         q[2].get<double>(),
                         q[3].get<double>()),
      Eigen::Vector3d(
          t[0].get<double>(), t[1].get<double>(), t[2].get<double>()));
}

// The cameras of `render --rig stereo` in `result` (a rig's
// calibration.json in `workspace`): both within 0.1 deg and 5 mm of their
// mounts (z from the floor), the pair within 0.1 deg and 5 mm, each camera's
// own files in cameras/<name>/ and the rig's robot files.
void ExpectStereoRigAccurate(const json& truth,
                             const json& result,
                             const fs::path& workspace,
                             const std::string& log) {
  ASSERT_EQ(result["cameras"].size(), 2u) << result["cameras"];
  std::map<std::string, Rigid3d> truths, estimates;
  for (size_t k = 0; k < 2; ++k) {
    const std::string name = truth["cameras"][k]["name"];
    const json& camera = result["cameras"][k];
    SCOPED_TRACE(name);
    ASSERT_EQ(camera["name"], name);
    ASSERT_EQ(camera["status"], "success") << camera["reason"] << log;
    truths[name] = TransformOf(truth["cameras"][k]["odom_from_cam"]);
    estimates[name] = TransformOf(camera["odom_from_cam"]);
    const Rigid3d error = Inverse(truths[name]) * estimates[name];
    std::cout << "[ errors   ] " << name << ": rotation "
              << RotationAngle(error.rotation) * kRadToDeg << " deg, "
              << "translation "
              << 1000.0 *
                     (estimates[name].translation - truths[name].translation)
                         .transpose()
              << " mm\n";
    EXPECT_LT(RotationAngle(error.rotation) * kRadToDeg, 0.1);
    EXPECT_LT((estimates[name].translation - truths[name].translation)
                  .head<2>()
                  .norm(),
              0.005);
    EXPECT_EQ(camera["translation_z_source"], "floor_plane");
    EXPECT_NEAR(
        estimates[name].translation.z(), truths[name].translation.z(), 0.005);
    EXPECT_TRUE(fs::exists(workspace / "cameras" / name / "calibration.json"));
  }
  // The pair: 12 cm apart along the odometry's y, the same orientation.
  ASSERT_EQ(result["camera_pairs"].size(), 1u);
  const json& pair = result["camera_pairs"][0];
  const Rigid3d expected =
      Inverse(truths[pair["camera_b"]]) * truths[pair["camera_a"]];
  const Rigid3d error = Inverse(expected) * TransformOf(pair["camb_from_cama"]);
  std::cout << "[ errors   ] pair: rotation "
            << RotationAngle(error.rotation) * kRadToDeg << " deg, "
            << "translation " << 1000.0 * error.translation.norm() << " mm\n";
  EXPECT_LT(RotationAngle(error.rotation) * kRadToDeg, 0.1);
  EXPECT_LT(error.translation.norm(), 0.005);
  const std::string urdf = ReadFile(workspace / "calibration.urdf");
  EXPECT_NE(urdf.find("left_camera_optical_frame"), std::string::npos);
  EXPECT_NE(urdf.find("right_camera_optical_frame"), std::string::npos);
  EXPECT_NE(ReadFile(workspace / "report.html").find("Cameras of the rig"),
            std::string::npos);
}

// A stereo pair (two forward cameras 12 cm apart, `render --rig stereo`)
// through `run --rig`: each camera from its own images in WS/cameras/<name>,
// z from the floor, and the camera-to-camera transform from the two.
TEST_F(RenderedEndToEnd, StereoRigThroughRunRig) {
  std::string log;
  const fs::path data = dir_ / "data";
  ASSERT_EQ(
      Run("render --preset small --rig stereo --seed " +
              std::to_string(TestSeed(5)) + " --output_path " + data.string(),
          &log),
      0)
      << log;
  const json truth = json::parse(ReadFile(data / "ground_truth.json"));
  std::string params_flags;
  for (const json& camera : truth["cameras"]) {
    std::string params;
    for (const json& value : camera["camera"]["params"]) {
      params += (params.empty() ? "" : ",") + FormatNumber(value.get<double>());
    }
    params_flags +=
        " --camera_params " + camera["name"].get<std::string>() + "=" + params;
  }
  const fs::path workspace = dir_ / "ws";
  ASSERT_EQ(Run("run --rig --image_path " + (data / "images").string() +
                    " --odometry " + (data / "odometry.csv").string() +
                    " --camera_model PINHOLE" + params_flags +
                    " --reference_camera right --workspace_path " +
                    workspace.string(),
                &log),
            0)
      << log;
  const json result = json::parse(ReadFile(workspace / "calibration.json"));
  EXPECT_EQ(result["reference_camera"], "right");
  ExpectStereoRigAccurate(truth, result, workspace, log);
}

// The stereo pair as a robot records it: a ROS 1 bag with two image topics
// and their CameraInfo (/left/image_raw/compressed, /left/camera_info,
// /right/..., written by python3-rosbag: rendered_to_ros1_bag.py), through
// `run --bag` with both --image_topic: a rig whose cameras are named by the
// topics' namespaces, each with the intrinsics of its CameraInfo. 30 images
// per camera (12 s of the drive) keep the test near a minute.
TEST_F(RenderedEndToEnd, StereoRigFromARos1BagWithTwoImageTopics) {
  std::string log;
  const fs::path data = dir_ / "data";
  const fs::path bag = dir_ / "bag" / "stereo.bag";
  fs::create_directories(bag.parent_path());
  ASSERT_EQ(
      Run("render --preset small --rig stereo --num_images 30 --seed " +
              std::to_string(TestSeed(5)) + " --output_path " + data.string(),
          &log),
      0)
      << log;
  const json truth = json::parse(ReadFile(data / "ground_truth.json"));
  ASSERT_EQ(std::system(("/usr/bin/python3 " ODOMCAL_BAG_FROM_RENDERING " " +
                         data.string() + " " + bag.string())
                            .c_str()),
            0);
  const auto bag_before = Snapshot(bag.parent_path());
  const fs::path workspace = dir_ / "ws";
  const auto start = std::chrono::steady_clock::now();
  ASSERT_EQ(Run("run --bag " + bag.string() +
                    " --image_topic /left/image_raw/compressed"
                    " --image_topic /right/image_raw/compressed"
                    " --workspace_path " +
                    workspace.string(),
                &log),
            0)
      << log;
  std::cout << "[ time     ] run --bag: "
            << std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                             start)
                   .count()
            << " s\n";
  EXPECT_TRUE(Snapshot(bag.parent_path()) == bag_before);
  const json result = json::parse(ReadFile(workspace / "calibration.json"));
  EXPECT_EQ(result["reference_camera"], "left");
  EXPECT_EQ(result["inputs"]["bag"], bag.string());
  EXPECT_EQ(result["inputs"]["rig"], true);
  EXPECT_EQ(result["options"]["bag"]["image_topic"],
            json::array(
                {"/left/image_raw/compressed", "/right/image_raw/compressed"}));
  ExpectStereoRigAccurate(truth, result, workspace, log);
  // The intrinsics came from each camera's CameraInfo, moved to COLMAP's
  // pixel centre.
  const std::string cameras =
      ReadFile(workspace / "bag_inputs" / "cameras.txt");
  EXPECT_NE(cameras.find("\n1 PINHOLE 320 240 260 260 160 120\n"),
            std::string::npos)
      << cameras;
  EXPECT_NE(cameras.find("\n2 PINHOLE 320 240 260 260 160 120\n"),
            std::string::npos)
      << cameras;
  for (const char* name : {"left", "right"}) {
    const json own = json::parse(
        ReadFile(workspace / "cameras" / name / "calibration.json"));
    EXPECT_EQ(own["options"]["run"]["camera_params"], "260,260,160,120")
        << name;
  }
}

}  // namespace
}  // namespace odomcal
