// A consumer of odomcal::plugin alone (the COLMAP integration of
// odomcal_plugin.h, with what it links itself: output, adapters, solver):
// a hand-made drive as a COLMAP text model, its odometry and image times,
// calibrated with CalibrateColmapProject; and ReconstructAndCalibrate
// refusing a missing image folder with an exception. Links only when no
// object of the plugin needs a symbol of a target that depends on it.
#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/timestamp.h"
#include "odomcal/adapters/trajectory_io.h"
#include "odomcal/plugin/odomcal_plugin.h"
#include "odomcal/solver/angles.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

constexpr double kPi = 3.14159265358979323846;

// A unicycle at 0.3 m/s with a yaw rate of two slow sines (turns both ways),
// odometry at 50 Hz for 60 s.
odomcal::Trajectory Odometry() {
  odomcal::Trajectory odometry;
  odometry.planar = true;
  double x = 0.0, y = 0.0, yaw = 0.0;
  const double dt = 0.02;
  for (int k = 0; k <= 3000; ++k) {
    const double t = k * dt;
    odometry.poses.push_back(
        {k * int64_t{20000000},
         odomcal::Rigid3d(odomcal::YawRotation(yaw), {x, y, 0.0})});
    const double yaw_rate =
        0.6 * std::sin(2 * kPi * t / 20.0) + 0.3 * std::sin(2 * kPi * t / 7.0);
    x += 0.3 * std::cos(yaw) * dt;
    y += 0.3 * std::sin(yaw) * dt;
    yaw += yaw_rate * dt;
  }
  return odometry;
}

}  // namespace

int main(int argc, char** argv) {
  const std::filesystem::path root =
      std::filesystem::path(argc > 1 ? argv[1]
                                     : std::filesystem::temp_directory_path()) /
      "plugin_only";
  std::filesystem::create_directories(root / "sparse" / "0");
  const odomcal::Trajectory odometry = Odometry();
  odomcal::WriteOdometryCsv(odometry, (root / "odometry.csv").string());

  // A forward-looking optical frame (z forward, x right, y down) 10 cm ahead
  // and 2 cm left of the odometry frame; 0.35 m per model unit.
  const odomcal::Rigid3d odom_from_cam(Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5),
                                       {0.10, 0.02, 0.0});
  const double metres_per_unit = 0.35;
  odomcal::ColmapModel model;
  odomcal::ColmapCamera camera;
  camera.camera_id = 1;
  camera.model = odomcal::ColmapCameraModel::kPinhole;
  camera.width = 320;
  camera.height = 240;
  camera.params = {250, 250, 160, 120};
  model.cameras[1] = camera;
  std::ofstream stamps(root / "image_timestamps.csv");
  stamps << "image_name,timestamp\n";
  for (size_t k = 0; k < odometry.poses.size(); k += 10) {  // 5 Hz
    odomcal::Rigid3d world_from_cam =
        odometry.poses[k].world_from_sensor * odom_from_cam;
    world_from_cam.translation /= metres_per_unit;
    odomcal::ColmapImage image;
    image.image_id = static_cast<uint32_t>(model.images.size() + 1);
    image.camera_id = 1;
    image.name = "frame" + std::to_string(k) + ".png";
    image.cam_from_world = odomcal::Inverse(world_from_cam);
    model.images[image.image_id] = image;
    stamps << image.name << ","
           << odomcal::FormatTimestampSeconds(odometry.poses[k].stamp_ns)
           << "\n";
  }
  stamps.close();
  odomcal::WriteColmapModel(
      model, (root / "sparse" / "0").string(), odomcal::ColmapFormat::kText);

  odomcal::ColmapCalibrationInputs inputs;
  inputs.model_path = (root / "sparse").string();
  inputs.odometry_path = (root / "odometry.csv").string();
  inputs.image_timestamps_path = (root / "image_timestamps.csv").string();
  const odomcal::ColmapCalibrationRun run =
      odomcal::CalibrateColmapProject(inputs);
  const odomcal::CalibrationResult& result = run.check.result;
  if (result.status != odomcal::CalibrationStatus::kSuccess) {
    std::fprintf(stderr, "plugin_only: %s\n", result.message.c_str());
    return 1;
  }
  const double rotation_error_deg =
      result.odom_from_cam.rotation.angularDistance(odom_from_cam.rotation) *
      odomcal::kRadToDeg;
  const double xy_error_m = (result.odom_from_cam.translation.head<2>() -
                             odom_from_cam.translation.head<2>())
                                .norm();
  const double scale_error =
      std::abs(result.metric_scales.at(0) / metres_per_unit - 1.0);
  std::printf(
      "plugin_only: rotation error %.2g deg, xy error %.2g m, "
      "scale error %.2g\n",
      rotation_error_deg,
      xy_error_m,
      scale_error);
  if (!(rotation_error_deg < 0.1 && xy_error_m < 1e-3 && scale_error < 1e-3)) {
    std::fprintf(stderr, "plugin_only: the drive's extrinsic not recovered\n");
    return 1;
  }

  odomcal::ReconstructionOptions options;
  options.image_path = (root / "no_such_images").string();
  options.project = inputs;
  options.workspace_path = (root / "workspace").string();
  try {
    odomcal::ReconstructAndCalibrate(options);
  } catch (const std::exception& error) {
    std::printf("plugin_only: ReconstructAndCalibrate refused: %s\n",
                error.what());
    return 0;
  }
  std::fprintf(stderr, "plugin_only: a missing image folder was accepted\n");
  return 1;
}
