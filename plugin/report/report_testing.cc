#include "odomcal/plugin/report/report_testing.h"

#include "odomcal/adapters/association.h"
#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/test_support.h"
#include "odomcal/adapters/timestamp.h"
#include "odomcal/adapters/trajectory_io.h"
#include "odomcal/datasets/simulation/drive_simulator.h"
#include "odomcal/plugin/options/cli_flags.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/calibrate.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <vector>

namespace odomcal {

namespace fs = std::filesystem;

double SimulatedImageMetricScale(const SimulatedColmapProjectOptions& options,
                                 size_t index,
                                 size_t num_images) {
  const double fraction =
      num_images > 1 ? static_cast<double>(index) / (num_images - 1) : 0.0;
  return DriveSimulatorOptions().metric_scale *
         (1.0 + options.scale_drift * fraction);
}

namespace {

// The points of SimulatedColmapProjectOptions::points_per_image, added to
// `model`: true points from the true cameras (origin_from_cam, metres),
// placed in the model through sfm_from_cam of their first image.
void AddSimulatedPoints(const SimulatedColmapProjectOptions& options,
                        const std::vector<Rigid3d>& origin_from_cam,
                        const std::vector<Rigid3d>& sfm_from_cam,
                        const std::vector<double>& metric_scales,
                        ColmapModel* model) {
  std::mt19937_64 random(options.seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 0.5);
  const ColmapCamera& camera = model->cameras.at(1);
  const double f = camera.params[0], cx = camera.params[2],
               cy = camera.params[3];
  const auto project = [&](const Eigen::Vector3d& in_cam) {
    return Eigen::Vector2d(f * in_cam.x() / in_cam.z() + cx,
                           f * in_cam.y() / in_cam.z() + cy);
  };
  int64_t next_id = 1;
  for (size_t k = 0; k < origin_from_cam.size(); ++k) {
    for (int n = 0; n < options.points_per_image; ++n) {
      // Within the image: a pixel, then a depth.
      const double depth = 2.0 + 6.0 * uniform(random);
      const Eigen::Vector3d in_cam(
          (uniform(random) * camera.width - cx) / f * depth,
          (uniform(random) * camera.height - cy) / f * depth,
          depth);
      const Eigen::Vector3d in_origin = origin_from_cam[k] * in_cam;
      ColmapPoint3D point;
      point.point3D_id = next_id;
      point.xyz = sfm_from_cam[k] * (in_cam / metric_scales[k]);
      // Feature tracks end: within kTrackImages of the point's first image.
      constexpr size_t kTrackImages = 20;
      for (size_t i = k; i < std::min(origin_from_cam.size(), k + kTrackImages);
           ++i) {
        const Eigen::Vector3d seen = Inverse(origin_from_cam[i]) * in_origin;
        if (seen.z() < 0.5 || seen.z() > 12.0) continue;
        const Eigen::Vector2d pixel =
            project(seen) + Eigen::Vector2d(normal(random), normal(random));
        if (pixel.x() < 0.0 || pixel.y() < 0.0 ||
            pixel.x() > static_cast<double>(camera.width) ||
            pixel.y() > static_cast<double>(camera.height)) {
          continue;
        }
        ColmapImage& image = model->images.at(static_cast<uint32_t>(i + 1));
        point.track.push_back(
            {image.image_id, static_cast<uint32_t>(image.points2D.size())});
        image.points2D.push_back({pixel, next_id});
      }
      if (point.track.size() < 2) {
        for (const ColmapTrackElement& element : point.track) {
          model->images.at(element.image_id)
              .points2D[element.point2D_idx]
              .point3D_id = kColmapNoPoint3D;
        }
        continue;
      }
      model->points3D.emplace(next_id++, std::move(point));
    }
  }
}

}  // namespace

ColmapCalibrationInputs WriteSimulatedColmapProject(
    const std::string& dir,
    const SimulatedColmapProjectOptions& options,
    SimulatedDrive* drive_out) {
  DriveSimulatorOptions drive_options;
  drive_options.seed = options.seed;
  drive_options.duration_s = options.duration_s;
  drive_options.camera_rotation_noise_deg = options.camera_rotation_noise_deg;
  drive_options.camera_position_noise =
      0.0005 * options.camera_rotation_noise_deg / 0.01;
  const SimulatedDrive drive = SimulateDrive(drive_options);

  const fs::path root(dir);
  fs::create_directories(root / "sparse" / "0");
  WriteOdometryCsv(drive.odometry, (root / "odometry.csv").string());
  std::ofstream stamps(root / "image_timestamps.csv");
  stamps << "image_name,timestamp\n";
  ColmapModel model;
  model.cameras[1] = MakeColmapCamera(
      1, ColmapCameraModel::kPinhole, 320, 240, {250, 250, 160, 120});
  const size_t num_images = drive.camera.poses.size();
  std::vector<Rigid3d> origin_from_cam, sfm_from_cam;
  std::vector<double> metric_scales;
  Eigen::Vector3d drifted_position = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < num_images; ++i) {
    Rigid3d world_from_cam = drive.camera.poses[i].world_from_sensor;
    if (i == 0) {
      drifted_position = world_from_cam.translation;
    } else {
      // A step of the drive in units of constant scale, re-expressed at the
      // step's drifted scale (mean of its two images').
      const double growth =
          0.5 *
          (SimulatedImageMetricScale(options, i - 1, num_images) +
           SimulatedImageMetricScale(options, i, num_images)) /
          drive.metric_scale;
      drifted_position +=
          (world_from_cam.translation -
           drive.camera.poses[i - 1].world_from_sensor.translation) /
          growth;
    }
    world_from_cam.translation = drifted_position;
    const size_t fold_first =
        options.fold_at_end ? (num_images > 30 ? num_images - 30 : 0) : 100;
    if (options.fold && i >= fold_first && i < fold_first + 30) {
      const double k = static_cast<double>(i - fold_first);
      world_from_cam.translation += Eigen::Vector3d(0.0, 0.0, 0.05 * k);
      world_from_cam.rotation =
          world_from_cam.rotation * Eigen::Quaterniond(Eigen::AngleAxisd(
                                        0.02 * k, Eigen::Vector3d::UnitX()));
    }
    if (static_cast<int>(i) == options.misregistered_image) {
      world_from_cam.translation += Eigen::Vector3d(0.5, 0.0, 0.0);
      world_from_cam.rotation =
          world_from_cam.rotation *
          Eigen::Quaterniond(
              Eigen::AngleAxisd(100.0 * kDegToRad, Eigen::Vector3d::UnitX()));
    }
    ColmapImage image;
    image.image_id = static_cast<uint32_t>(i + 1);
    image.camera_id = 1;
    char name[32];
    std::snprintf(name, sizeof(name), "frames/%06zu.png", i);
    image.name = name;
    image.cam_from_world = Inverse(world_from_cam);
    model.images[image.image_id] = image;
    stamps << image.name << ","
           << FormatTimestampSeconds(drive.camera.poses[i].stamp_ns) << "\n";
    if (options.points_per_image > 0) {
      const auto origin_from_odom = InterpolateOdometry(
          drive.true_odometry, drive.camera.poses[i].stamp_ns, 1.0, nullptr);
      origin_from_cam.push_back(origin_from_odom.value() * drive.odom_from_cam);
      sfm_from_cam.push_back(world_from_cam);
      metric_scales.push_back(
          SimulatedImageMetricScale(options, i, num_images));
    }
  }
  if (options.points_per_image > 0) {
    AddSimulatedPoints(
        options, origin_from_cam, sfm_from_cam, metric_scales, &model);
  }
  if (drive_out != nullptr) *drive_out = drive;
  WriteColmapModel(
      model, (root / "sparse" / "0").string(), ColmapFormat::kBinary);

  ColmapCalibrationInputs inputs;
  inputs.model_path = (root / "sparse").string();
  inputs.odometry_path = (root / "odometry.csv").string();
  inputs.image_timestamps_path = (root / "image_timestamps.csv").string();
  inputs.calibration.fixed_translation_z_m = 0.4;
  return inputs;
}

CalibrationRun SimulatedCalibrationRun(uint64_t seed, bool straight_only) {
  DriveSimulatorOptions drive_options;
  drive_options.seed = seed;
  drive_options.duration_s = 40.0;
  drive_options.straight_only = straight_only;
  drive_options.camera_rotation_noise_deg = 0.01;
  drive_options.camera_position_noise = 0.0005;
  const SimulatedDrive drive = SimulateDrive(drive_options);
  CalibrationRun run;
  ReportContext& context = run.context;
  context.command = "odomcal calibrate";
  context.camera_paths = {"camera.tum"};
  context.odometry_path = "odometry.csv";
  context.camera_time_unit = "s";
  context.odometry_time_unit = "s";
  context.calibration_options.fixed_translation_z_m = 0.4;
  context.flag_echo = CalibrationFlagsEcho(context.association_options,
                                           context.calibration_options);
  context.association = AssociateCameraWithOdometry(
      {drive.camera}, drive.odometry, context.association_options);
  run.result =
      CalibrateOdomCam(context.association.pairs, context.calibration_options);
  return run;
}

}  // namespace odomcal
