// `odomcal colmap` on a COLMAP project with several cameras: a simulated
// robot with three cameras (each its own COLMAP camera and image sub-folder,
// its own rate, phase and clock offset), reconstructed together in two
// sub-models. Checks that every camera is calibrated from its own images
// within its stated 3 sigma, that the cameras agree on the scale of the
// sub-models they share, that each camera's files are written, that a
// camera which cannot be calibrated is named while the others are written,
// and the --reference_camera errors.

#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/test_support.h"
#include "odomcal/adapters/timestamp.h"
#include "odomcal/adapters/trajectory_io.h"
#include "odomcal/datasets/simulation/camera_mount.h"
#include "odomcal/datasets/simulation/drive_simulator.h"
#include "odomcal/plugin/cli/colmap_rig_outputs.h"
#include "odomcal/plugin/colmap/colmap_rig_calibration.h"
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
#include <random>
#include <set>
#include <string>
#include <vector>

namespace odomcal {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct RigCamera {
  std::string name;
  Rigid3d odom_from_cam;
  double rate_hz = 5.0;
  double phase_s = 0.0;         // first frame after the drive's start
  double clock_offset_s = 0.0;  // its stamps are true time - this
  double duration_s = 1e9;      // frames only this long after the start
};

std::vector<RigCamera> ThreeCameras() {
  return {
      {"front",
       MakeCameraMount(30.0, 10.0, 0.0, {0.30, 0.10, 0.50}),
       5.0,
       0.0,
       0.0},
      {"rear",
       MakeCameraMount(180.0, 15.0, 0.0, {-0.20, 0.05, 0.50}),
       4.0,
       0.03,
       0.02},
      {"right",
       MakeCameraMount(-90.0, 5.0, 2.0, {0.05, -0.20, 0.50}),
       5.0,
       0.115,
       -0.015},
  };
}

class ColmapRigCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(::testing::TempDir()) /
           (std::string("odomcal_colmap_rig_cli_") + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "project" / "sparse");
  }
  void TearDown() override {
    if (std::getenv("ODOMCAL_KEEP_TEST_FILES") == nullptr) fs::remove_all(dir_);
  }

  std::string Path(const std::string& name) const {
    return (dir_ / name).string();
  }

  int Run(const std::string& arguments,
          std::string* out = nullptr,
          std::string* err = nullptr) const {
    const fs::path out_path = dir_ / "stdout.txt",
                   err_path = dir_ / "stderr.txt";
    const std::string command = std::string(ODOMCAL_EXECUTABLE) + " " +
                                arguments + " > " + out_path.string() + " 2> " +
                                err_path.string();
    const int status = std::system(command.c_str());
    if (out != nullptr) *out = ReadFile(out_path);
    if (err != nullptr) *err = ReadFile(err_path);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  // odometry.csv, and a project whose sub-model 0 holds every camera's
  // images of the first 60 % of the drive and sub-model 1 the rest (10
  // shared seconds), each sub-model in its own similarity frame; camera k is
  // COLMAP camera k + 1 with images "<name>/<index>.png". With
  // `with_points`, 3D points ahead of every camera and every image's
  // observations of them (0.5 px noise), as COLMAP's tracks.
  void WriteProject(uint64_t seed,
                    const std::vector<RigCamera>& cameras,
                    bool with_points = false,
                    double duration_s = 90.0) {
    DriveSimulatorOptions options;
    options.seed = seed;
    options.duration_s = duration_s;
    options.odometry_rate_hz = 200.0;
    options.wheel_scale_error_left = 0.002;
    options.wheel_scale_error_right = -0.002;
    const SimulatedDrive drive = SimulateDrive(options);
    WriteOdometryCsv(drive.odometry, Path("odometry.csv"));
    std::mt19937_64 rng(seed * 7919 + 3);
    std::normal_distribution<double> gauss(0.0, 1.0);
    const int64_t start_ns = drive.true_odometry.poses.front().stamp_ns;
    std::ofstream stamps(dir_ / "project" / "image_timestamps.csv");
    stamps << "image_name,timestamp\n";
    const Rigid3d frames[2] = {
        Rigid3d(Eigen::Quaterniond(0.9, 0.1, -0.3, 0.2).normalized(),
                Eigen::Vector3d(0.5, -1.0, 2.0)),
        Rigid3d(Eigen::Quaterniond(0.2, 0.7, 0.1, -0.4).normalized(),
                Eigen::Vector3d(-3.0, 1.0, 0.5))};
    const double units_per_metre[2] = {1.0 / 0.37, 1.0 / 1.9};
    const double split_s = 0.6 * duration_s;
    ColmapModel models[2];
    // Per sub-model, each image's id and true world_from_cam (metres).
    std::vector<std::pair<uint32_t, Rigid3d>> true_poses[2];
    for (size_t c = 0; c < cameras.size(); ++c) {
      const uint32_t camera_id = static_cast<uint32_t>(c + 1);
      for (ColmapModel& model : models) {
        model.cameras[camera_id] = MakeColmapCamera(camera_id,
                                                    ColmapCameraModel::kPinhole,
                                                    320,
                                                    240,
                                                    {250, 250, 160, 120});
      }
      const RigCamera& camera = cameras[c];
      const int64_t period_ns = std::llround(1e9 / camera.rate_hz);
      const int64_t phase_ns = std::llround(1e9 * camera.phase_s);
      int index = 0;
      for (const StampedPose& pose : drive.true_odometry.poses) {
        const int64_t since_start_ns = pose.stamp_ns - start_ns - phase_ns;
        if (since_start_ns < 0 || since_start_ns % period_ns != 0 ||
            since_start_ns > std::llround(1e9 * camera.duration_s)) {
          continue;
        }
        const double t_s = 1e-9 * static_cast<double>(since_start_ns);
        char name[64];
        std::snprintf(
            name, sizeof(name), "%s/%06d.png", camera.name.c_str(), index++);
        stamps << name << ","
               << FormatTimestampSeconds(
                      pose.stamp_ns - std::llround(1e9 * camera.clock_offset_s))
               << "\n";
        for (int part = 0; part < 2; ++part) {
          if ((part == 0 && t_s > split_s) ||
              (part == 1 && t_s < split_s - 10.0))
            continue;
          true_poses[part].emplace_back(
              static_cast<uint32_t>(models[part].images.size() + 1),
              pose.world_from_sensor * camera.odom_from_cam);
          Rigid3d world_from_cam =
              frames[part] * pose.world_from_sensor * camera.odom_from_cam;
          world_from_cam.translation *= units_per_metre[part];
          const Eigen::Vector3d rotation_noise(
              gauss(rng), gauss(rng), gauss(rng));
          const Eigen::Vector3d position_noise(
              gauss(rng), gauss(rng), gauss(rng));
          world_from_cam.rotation =
              (ExpRotation(rotation_noise * 0.02 * kDegToRad) *
               world_from_cam.rotation)
                  .normalized();
          world_from_cam.translation +=
              0.001 * units_per_metre[part] * position_noise;
          ColmapImage image;
          image.image_id =
              static_cast<uint32_t>(models[part].images.size() + 1);
          image.camera_id = camera_id;
          image.name = name;
          image.cam_from_world = Inverse(world_from_cam);
          models[part].images[image.image_id] = image;
        }
      }
    }
    if (with_points) {
      AddPoints(true_poses, frames, units_per_metre, &rng, models);
    }
    for (int part = 0; part < 2; ++part) {
      const fs::path folder =
          dir_ / "project" / "sparse" / std::to_string(part);
      fs::create_directories(folder);
      WriteColmapModel(models[part], folder.string(), ColmapFormat::kBinary);
    }
  }

  // Points 3-9 m ahead of every image's camera (world, metres), seen by
  // every image of a sub-model that has them in its 320 x 240 view.
  static void AddPoints(
      const std::vector<std::pair<uint32_t, Rigid3d>> (&true_poses)[2],
      const Rigid3d (&frames)[2],
      const double (&units_per_metre)[2],
      std::mt19937_64* rng,
      ColmapModel (&models)[2]) {
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    std::normal_distribution<double> gauss(0.0, 1.0);
    std::vector<Eigen::Vector3d> points;
    for (const auto& poses : true_poses) {
      for (const auto& [id, world_from_cam] : poses) {
        for (int k = 0; k < 2; ++k) {
          const double depth = 6.0 + 3.0 * uniform(*rng);
          points.push_back(world_from_cam *
                           Eigen::Vector3d(0.6 * depth * uniform(*rng),
                                           0.45 * depth * uniform(*rng),
                                           depth));
        }
      }
    }
    for (int part = 0; part < 2; ++part) {
      ColmapModel& model = models[part];
      for (const auto& [id, world_from_cam] : true_poses[part]) {
        ColmapImage& image = model.images.at(id);
        const Rigid3d cam_from_world = Inverse(world_from_cam);
        for (size_t p = 0; p < points.size(); ++p) {
          const Eigen::Vector3d in_cam = cam_from_world * points[p];
          if (in_cam.z() < 0.5 || in_cam.z() > 12.0) continue;
          const Eigen::Vector2d pixel(
              250.0 * in_cam.x() / in_cam.z() + 160.0 + 0.5 * gauss(*rng),
              250.0 * in_cam.y() / in_cam.z() + 120.0 + 0.5 * gauss(*rng));
          if (pixel.x() < 0.0 || pixel.x() > 320.0 || pixel.y() < 0.0 ||
              pixel.y() > 240.0) {
            continue;
          }
          const int64_t point_id = static_cast<int64_t>(p + 1);
          ColmapPoint3D& point = model.points3D[point_id];
          point.point3D_id = point_id;
          point.xyz = units_per_metre[part] * (frames[part] * points[p]);
          point.track.push_back(
              {id, static_cast<uint32_t>(image.points2D.size())});
          image.points2D.push_back({pixel, point_id});
        }
      }
    }
  }

  std::string Arguments() const {
    return "colmap --model_path " + Path("project/sparse") + " --odometry " +
           Path("odometry.csv") + " --image_timestamps " +
           Path("project/image_timestamps.csv") + " --output_path " +
           Path("out") + " --fixed_translation_z_m 0.5";
  }

  fs::path dir_;
};

TEST_F(ColmapRigCli, EveryCameraCalibratedFromItsOwnImages) {
  const uint64_t seed = TestSeed(41);
  SCOPED_TRACE("seed " + std::to_string(seed));
  const std::vector<RigCamera> cameras = ThreeCameras();
  WriteProject(seed, cameras);
  const auto before = Snapshot(dir_ / "project");
  std::string out, err;
  ASSERT_EQ(Run(Arguments() + " --reference_camera rear", &out, &err), 0)
      << out << err;
  EXPECT_EQ(Snapshot(dir_ / "project"), before) << "the input project changed";
  EXPECT_NE(out.find("cameras: 3 (one camera per image sub-folder): front ("),
            std::string::npos)
      << out;

  const json result = json::parse(ReadFile(dir_ / "out" / "calibration.json"));
  EXPECT_EQ(result["reference_camera"], "rear");
  EXPECT_EQ(result["inputs"]["reference_camera"], "rear");
  EXPECT_EQ(result["camera_grouping"], "one camera per image sub-folder");
  ASSERT_EQ(result["cameras"].size(), 3u);
  for (size_t k = 0; k < cameras.size(); ++k) {
    const json& camera = result["cameras"][k];
    SCOPED_TRACE(cameras[k].name);
    EXPECT_EQ(camera["name"], cameras[k].name);
    ASSERT_EQ(camera["status"], "success") << camera["reason"];
    EXPECT_EQ(camera["colmap_camera_ids"], json::array({k + 1}));
    ExpectWithinThreeSigma("camera",
                           cameras[k].odom_from_cam,
                           camera["odom_from_cam"],
                           camera["covariance"],
                           /*z_held=*/true);
    // Two sub-models, each with this camera's images at its own scale.
    ASSERT_EQ(camera["metric_scales"].size(), 2u);
    EXPECT_NEAR(camera["metric_scales"][0].get<double>(), 0.37, 0.37 * 0.01);
    EXPECT_NEAR(camera["metric_scales"][1].get<double>(), 1.9, 1.9 * 0.01);
    EXPECT_NEAR(camera["camera_time_offset_s"].get<double>(),
                cameras[k].clock_offset_s,
                0.005);
    // The camera's own files.
    const fs::path own = dir_ / "out" / "cameras" / cameras[k].name;
    EXPECT_EQ(camera["outputs"], "cameras/" + cameras[k].name + "/");
    const json alone = json::parse(ReadFile(own / "calibration.json"));
    EXPECT_EQ(alone["odom_from_cam"], camera["odom_from_cam"]);
    EXPECT_TRUE(fs::exists(own / "report.html"));
    EXPECT_TRUE(fs::is_directory(own / "sparse_metric" / "0"));
  }
  EXPECT_EQ(result["odom_from_cam"], result["cameras"][1]["odom_from_cam"]);
  EXPECT_EQ(result["camera_pairs"].size(), 3u);
  // Three pairs of cameras, two shared sub-models each, none disagreeing.
  ASSERT_EQ(result["shared_scales"].size(), 6u);
  for (const json& shared : result["shared_scales"]) {
    EXPECT_FALSE(shared["disagree"].get<bool>()) << shared;
  }
  const std::string urdf = ReadFile(dir_ / "out" / "calibration.urdf");
  for (const RigCamera& camera : cameras) {
    EXPECT_NE(urdf.find(camera.name + "_camera_optical_frame"),
              std::string::npos)
        << urdf;
  }
  // The top report shows the rig: every camera with a link to its own
  // report and a pyramid in the drawing, and the rig's robot outputs.
  const std::string report = ReadFile(dir_ / "out" / "report.html");
  const size_t section = report.find("<h2>Cameras of the rig</h2>");
  ASSERT_NE(section, std::string::npos);
  EXPECT_NE(report.find("3 of 3 cameras calibrated", section),
            std::string::npos);
  EXPECT_NE(report.find("</span> rear<br><span "
                        "style=\"white-space:nowrap\">(reference)</span></td>"),
            std::string::npos);
  for (const RigCamera& camera : cameras) {
    EXPECT_NE(
        report.find("<a href=\"cameras/" + camera.name + "/report.html\">",
                    section),
        std::string::npos)
        << camera.name;
    // Named in the legend and beside its pyramid in both views.
    size_t count = 0;
    for (size_t at = report.find(">" + camera.name + "</text>", section);
         at != std::string::npos;
         at = report.find(">" + camera.name + "</text>", at + 1)) {
      ++count;
    }
    EXPECT_EQ(count, 3u) << camera.name;
  }
  EXPECT_NE(report.find("Frames: base_link &rarr; front_camera_optical_frame, "
                        "base_link &rarr; rear_camera_optical_frame, base_link "
                        "&rarr; right_camera_optical_frame ",
                        section),
            std::string::npos)
      << "the rig's robot outputs under Use it";
  EXPECT_NE(report.find("<table class=\"rig-pairs\">"), std::string::npos);
  EXPECT_EQ(report.find("class=\"disagree\""), std::string::npos);
  const std::string rig_section =
      report.substr(section, report.find("</section>", section) - section);
  EXPECT_EQ(rig_section.find("nan"), std::string::npos);
  EXPECT_EQ(rig_section.find("inf"), std::string::npos);

  // A rerun as a single camera's project removes the rig's cameras/.
  fs::remove_all(dir_ / "project" / "sparse" / "1");
  ColmapModel model = ReadColmapModel(Path("project/sparse/0"));
  for (auto it = model.images.begin(); it != model.images.end();) {
    it = it->second.camera_id == 1 ? std::next(it) : model.images.erase(it);
  }
  model.cameras.erase(2);
  model.cameras.erase(3);
  WriteColmapModel(model, Path("project/sparse/0"), ColmapFormat::kBinary);
  ASSERT_EQ(Run(Arguments() + " --overwrite", &out, &err), 0) << out << err;
  EXPECT_FALSE(fs::exists(dir_ / "out" / "cameras"));
  EXPECT_EQ(ReadFile(dir_ / "out" / "report.html").find("Cameras of the rig"),
            std::string::npos);
  EXPECT_FALSE(json::parse(ReadFile(dir_ / "out" / "calibration.json"))
                   .contains("cameras"));
}

// `--joint_adjustment on`: the three cameras, their images' points and the
// odometry in one adjustment; every camera and every camera-to-camera
// transform near the truth by its stated sigma, the transforms with the
// adjustment's cross terms and tighter than the cameras calibrated apart
// state them.
TEST_F(ColmapRigCli, JointAdjustmentOnAdjustsEveryCameraTogether) {
  const uint64_t seed = TestSeed(43);
  SCOPED_TRACE("seed " + std::to_string(seed));
  const std::vector<RigCamera> cameras = ThreeCameras();
  WriteProject(seed, cameras, /*with_points=*/true, /*duration_s=*/30.0);
  std::string out, err;
  const std::string arguments =
      Arguments() + " --joint_jackknife_blocks 0 --overwrite";
  ASSERT_EQ(Run(arguments + " --joint_adjustment off", &out, &err), 0)
      << out << err;
  const json apart = json::parse(ReadFile(dir_ / "out" / "calibration.json"));
  EXPECT_TRUE(apart["rig_joint_adjustment"].is_null());
  // The default, a check: the cameras adjusted together agree with each
  // camera's own estimate on this clean drive, which stands, with the
  // pairs of independent estimates.
  ASSERT_EQ(Run(arguments, &out, &err), 0) << out << err;
  EXPECT_NE(out.find("rig joint adjustment check: every camera's own "
                     "estimate stands"),
            std::string::npos)
      << out;
  const json checked = json::parse(ReadFile(dir_ / "out" / "calibration.json"));
  const json& check = checked["rig_joint_adjustment"];
  ASSERT_TRUE(check.is_object()) << checked.dump(1);
  EXPECT_EQ(check["use"], "check");
  EXPECT_EQ(check["status"], "success") << check["message"];
  EXPECT_FALSE(check["adopted"].get<bool>());
  EXPECT_LE(check["max_disagreement_sigmas"].get<double>(), 3.0);
  EXPECT_TRUE(check["max_disagreement_sigmas_jackknifed"].is_null());
  for (size_t k = 0; k < cameras.size(); ++k) {
    EXPECT_EQ(checked["cameras"][k]["odom_from_cam"],
              apart["cameras"][k]["odom_from_cam"]);
  }
  for (const json& pair : checked["camera_pairs"]) {
    EXPECT_FALSE(pair["adjusted_together"].get<bool>());
  }
  EXPECT_NE(ReadFile(dir_ / "out" / "report.html").find("own estimate stands"),
            std::string::npos);
  ASSERT_EQ(Run(arguments + " --joint_adjustment on", &out, &err), 0)
      << out << err;
  EXPECT_NE(out.find("rig joint adjustment: front, rear, right adjusted "
                     "together"),
            std::string::npos)
      << out;
  const json result = json::parse(ReadFile(dir_ / "out" / "calibration.json"));
  const json& joint = result["rig_joint_adjustment"];
  ASSERT_TRUE(joint.is_object()) << result.dump(1);
  EXPECT_EQ(joint["use"], "on");
  EXPECT_TRUE(joint["adopted"].get<bool>());
  EXPECT_EQ(joint["status"], "success") << joint["message"];
  EXPECT_EQ(joint["cameras"], json::array({"front", "rear", "right"}));
  EXPECT_GT(joint["num_links_across_cameras"].get<int>(),
            joint["num_links"].get<int>() / 2);
  // The project's points seen by several cameras are one point each.
  EXPECT_GT(joint["num_points_across_cameras"].get<int>(), 0);
  EXPECT_NE(out.find("seen by several cameras"), std::string::npos) << out;
  // Each camera's estimated clock offset, held, enters by its uncertainty.
  EXPECT_EQ(joint["num_clock_offsets_propagated"], 3);
  // No database: whether COLMAP changed the intrinsics is not known, so
  // --joint_intrinsics auto holds them, and says so per camera.
  std::set<std::string> with_intrinsics;
  for (const json& camera : joint["camera_intrinsics"]) {
    with_intrinsics.insert(camera["camera"].get<std::string>());
    EXPECT_FALSE(camera["refined"].get<bool>());
    EXPECT_EQ(camera["params"], camera["params_before"]);
  }
  EXPECT_EQ(with_intrinsics, std::set<std::string>({"front", "rear", "right"}));
  const std::string report = ReadFile(dir_ / "out" / "report.html");
  EXPECT_NE(report.find("Then adjusted together with the odometry"),
            std::string::npos);
  EXPECT_NE(report.find("points of the reconstruction are seen by several "
                        "cameras' images"),
            std::string::npos);
  EXPECT_NE(report.find("3-sigma bounds from the rig's joint adjustment"),
            std::string::npos);
  // 15 camera and 18 pair errors over their sigmas. With honest sigmas
  // about 1 in 10 such runs has one beyond 3 by chance: each within 4, and
  // their root mean square near 1 (an understated sigma shows in it).
  std::vector<double> errors;
  const auto add = [&](const std::vector<double>& more) {
    for (const double e : more) {
      std::cout << "normalised error " << e << "\n";
      EXPECT_LT(std::abs(e), 4.0);
      errors.push_back(e);
    }
  };
  for (size_t k = 0; k < cameras.size(); ++k) {
    SCOPED_TRACE(cameras[k].name);
    const json& camera = result["cameras"][k];
    ASSERT_EQ(camera["status"], "success") << camera["reason"];
    add(NormalisedErrors(cameras[k].odom_from_cam,
                         camera["odom_from_cam"],
                         camera["covariance"],
                         /*z_held=*/true));
  }
  ASSERT_EQ(result["camera_pairs"].size(), 3u);
  const auto truth_of = [&](const json& name) {
    for (const RigCamera& camera : cameras) {
      if (camera.name == name) return camera.odom_from_cam;
    }
    return Rigid3d();
  };
  for (size_t p = 0; p < 3; ++p) {
    const json& pair = result["camera_pairs"][p];
    SCOPED_TRACE(pair["camera_b"].get<std::string>() + "_from_" +
                 pair["camera_a"].get<std::string>());
    EXPECT_TRUE(pair["adjusted_together"].get<bool>());
    EXPECT_FALSE(apart["camera_pairs"][p]["adjusted_together"].get<bool>());
    add(NormalisedErrors(
        Inverse(truth_of(pair["camera_b"])) * truth_of(pair["camera_a"]),
        pair["camb_from_cama"],
        pair["covariance"],
        /*z_held=*/false));
    // The trajectory's errors common to both cameras cancel in the pair.
    for (int k = 0; k < 3; ++k) {
      EXPECT_LT(pair["stddev"]["rotation_axes_deg"][k].get<double>(),
                apart["camera_pairs"][p]["stddev"]["rotation_axes_deg"][k]
                    .get<double>())
          << "axis " << k;
    }
  }
  double sum_squares = 0.0;
  for (const double e : errors) sum_squares += e * e;
  const double rms =
      std::sqrt(sum_squares / static_cast<double>(errors.size()));
  EXPECT_GT(rms, 0.3);
  EXPECT_LT(rms, 1.6);
}

// The rig's default check where one camera's own estimate is off: the
// rear camera's two-step yaw moved by 0.5 deg (about 7 of its sigmas)
// before the cameras are adjusted together. The adjustment, from the
// images and the odometry, contradicts it, and is reported for every
// camera with the cross terms; the same cameras without the move leave
// their own estimates standing (the test above).
TEST_F(ColmapRigCli, RigCheckReportsTheAdjustmentWhereACameraIsContradicted) {
  const uint64_t seed = TestSeed(47);
  SCOPED_TRACE("seed " + std::to_string(seed));
  const std::vector<RigCamera> cameras = ThreeCameras();
  WriteProject(seed, cameras, /*with_points=*/true, /*duration_s=*/20.0);
  ColmapCalibrationInputs inputs;
  inputs.model_path = Path("project/sparse");
  inputs.odometry_path = Path("odometry.csv");
  inputs.image_timestamps_path = Path("project/image_timestamps.csv");
  inputs.calibration.fixed_translation_z_m = 0.5;
  inputs.joint_adjustment.use = JointAdjustmentUse::kOff;
  inputs.joint_adjustment.jackknife.num_blocks = 0;
  ColmapRigRun rig = CalibrateColmapRig(
      inputs, FindColmapProjectCameras(inputs.model_path), 0);
  ASSERT_EQ(rig.cameras.size(), 3u);
  ASSERT_EQ(rig.cameras[1].camera.name, "rear");
  ASSERT_TRUE(rig.cameras[1].run);
  CalibrationResult& rear = rig.cameras[1].run->check.result;
  ASSERT_TRUE(rear.IsSuccess()) << rear.message;
  const Rigid3d rear_before = rear.odom_from_cam;
  rear.odom_from_cam.rotation =
      Eigen::Quaterniond(
          Eigen::AngleAxisd(0.5 * kDegToRad, Eigen::Vector3d::UnitZ())) *
      rear.odom_from_cam.rotation;

  inputs.joint_adjustment.use = JointAdjustmentUse::kCheck;
  AdjustColmapRigJointly(inputs, {}, &rig);
  const RigJointAdjustment& joint = rig.joint;
  ASSERT_TRUE(joint.Succeeded()) << joint.result.message << joint.skipped;
  EXPECT_EQ(joint.use, JointAdjustmentUse::kCheck);
  EXPECT_GT(joint.max_disagreement_sigmas, 3.0);
  ASSERT_FALSE(joint.disagreements.empty());
  for (const RigDisagreement& d : joint.disagreements) {
    EXPECT_EQ(d.camera, 1) << d.quantity.quantity;
  }
  EXPECT_TRUE(joint.Adopted());
  EXPECT_GE(joint.max_disagreement_sigmas_jackknifed, 0.0);
  // The adjustment's rear camera is back near its estimate before the move.
  const int mount = joint.MountOf(1);
  ASSERT_GE(mount, 0);
  const Rigid3d& adjusted = joint.result.MountOdomFromCam(mount);
  EXPECT_LT(adjusted.rotation.angularDistance(rear_before.rotation) * kRadToDeg,
            0.1);

  // Taken into the rig: every camera's extrinsic the adjustment's, the
  // pairs with its cross terms, and the contradiction named.
  RigCalibrationRun as_rig = RigCalibrationOf(rig, "odomcal colmap", {});
  for (const RigCameraPair& pair : as_rig.pairs) {
    EXPECT_TRUE(pair.adjusted_together);
  }
  EXPECT_LT(as_rig.cameras[1].run.result.odom_from_cam.rotation.angularDistance(
                rear_before.rotation) *
                kRadToDeg,
            0.1);
  bool named = false;
  for (const std::string& finding : as_rig.findings) {
    if (finding.rfind("rig joint adjustment check: camera rear's yaw", 0) ==
        0) {
      named = true;
    }
  }
  EXPECT_TRUE(named);
}

// A camera that saw only its first seconds: named with its reason, the
// others calibrated and written, exit 0.
TEST_F(ColmapRigCli, CameraWithTooFewImagesIsNamedAndTheOthersAreWritten) {
  std::vector<RigCamera> cameras = ThreeCameras();
  cameras[2].duration_s = 1.0;
  WriteProject(TestSeed(42), cameras);
  std::string out, err;
  ASSERT_EQ(Run(Arguments(), &out, &err), 0) << out << err;
  EXPECT_NE(err.find("odomcal colmap: warning: camera right not calibrated"),
            std::string::npos)
      << err;
  const json result = json::parse(ReadFile(dir_ / "out" / "calibration.json"));
  EXPECT_EQ(result["reference_camera"], "front");
  EXPECT_EQ(result["cameras"][0]["status"], "success");
  EXPECT_EQ(result["cameras"][1]["status"], "success");
  EXPECT_NE(result["cameras"][2]["status"], "success");
  EXPECT_FALSE(result["cameras"][2]["reason"].get<std::string>().empty());
  ASSERT_EQ(result["camera_pairs"].size(), 1u);
  EXPECT_NE(ReadFile(dir_ / "out" / "report.html")
                .find("<td colspan=\"6\" class=\"reason\">not calibrated: "),
            std::string::npos);
  EXPECT_TRUE(
      fs::exists(dir_ / "out" / "cameras" / "rear" / "calibration.json"));
}

TEST_F(ColmapRigCli, ReferenceCameraErrorsNameTheFlag) {
  std::vector<RigCamera> cameras = ThreeCameras();
  cameras.resize(2);
  WriteProject(TestSeed(43), cameras);
  std::string err;
  EXPECT_EQ(Run(Arguments() + " --reference_camera side", nullptr, &err), 2);
  EXPECT_EQ(err,
            "odomcal colmap: error: --reference_camera 'side' names no camera "
            "of the project (its cameras: front, rear)\n");
  EXPECT_FALSE(fs::exists(dir_ / "out" / "calibration.json"));

  cameras.resize(1);
  fs::remove_all(dir_ / "project");
  fs::create_directories(dir_ / "project" / "sparse");
  WriteProject(TestSeed(43), cameras);
  EXPECT_EQ(Run(Arguments() + " --reference_camera front", nullptr, &err), 2);
  EXPECT_EQ(err,
            "odomcal colmap: error: --reference_camera: the project has one "
            "camera (one camera); the option is for a project with several\n");
  EXPECT_FALSE(fs::exists(dir_ / "out" / "calibration.json"));
}

}  // namespace
}  // namespace odomcal

namespace odomcal {
namespace {

// The reference camera's images fit no odometry time (another clock): it is
// named with its input error, the other cameras are calibrated and written,
// and the top level says so without a model of its own.
TEST_F(ColmapRigCli, ReferenceCameraWithAnInputErrorLeavesTheOthers) {
  std::vector<RigCamera> cameras = ThreeCameras();
  cameras[0].clock_offset_s = 5000.0;
  WriteProject(TestSeed(44), cameras);
  std::string out, err;
  ASSERT_EQ(Run(Arguments(), &out, &err), 0) << out << err;
  const json result = json::parse(ReadFile(dir_ / "out" / "calibration.json"));
  EXPECT_EQ(result["reference_camera"], "front");
  EXPECT_EQ(result["cameras"][0]["status"], "input_error");
  EXPECT_TRUE(result["cameras"][0]["outputs"].is_null());
  EXPECT_EQ(result["cameras"][1]["status"], "success");
  EXPECT_EQ(result["cameras"][2]["status"], "success");
  EXPECT_EQ(result["camera_pairs"].size(), 1u);
  EXPECT_NE(err.find("warning: camera front not calibrated (input_error)"),
            std::string::npos)
      << err;
  EXPECT_TRUE(fs::exists(dir_ / "out" / "report.html"));
  EXPECT_FALSE(fs::exists(dir_ / "out" / "cameras" / "front"));
  EXPECT_TRUE(fs::exists(dir_ / "out" / "cameras" / "rear" / "report.html"));
  EXPECT_NE(ReadFile(dir_ / "out" / "calibration.urdf")
                .find("rear_camera_optical_frame"),
            std::string::npos);
}

}  // namespace
}  // namespace odomcal
