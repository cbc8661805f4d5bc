// A downstream project using the installed package: find_package(odomcal)
// and one call into every exported library. datasets_simulation simulates a
// noise-free drive, adapters writes it as files (trajectories, and a COLMAP
// text model with image timestamps) and associates it, solver calibrates the
// pairs, datasets_paper runs Chang et al.'s baseline on them,
// datasets_rendering measures a room, plugin calibrates the COLMAP project
// (odomcal_plugin.h), output claims the output folder, options and reports
// echo the options and write the files, and cli runs the `odomcal
// calibrate` pipeline on the trajectory files. Every estimate must recover
// the simulated extrinsic and scale.
#include "odomcal/adapters/association.h"
#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/timestamp.h"
#include "odomcal/adapters/trajectory_io.h"
#include "odomcal/datasets/paper/chang_baseline.h"
#include "odomcal/datasets/rendering/room_layout.h"
#include "odomcal/datasets/simulation/drive_simulator.h"
#include "odomcal/plugin/cli/calibrate_command.h"
#include "odomcal/plugin/odomcal_plugin.h"
#include "odomcal/plugin/output/output_folder.h"
#include "odomcal/plugin/report/calibration_report.h"
#include "odomcal/plugin/report/colmap_calibration_outputs.h"
#include "odomcal/plugin/report/colmap_report.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/calibrate.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

bool Check(bool ok, const std::string& what) {
  if (!ok) std::fprintf(stderr, "consumer: %s\n", what.c_str());
  return ok;
}

// Rotation error (deg), x/y translation error (m) and scale error (relative);
// z is unobservable under planar motion and held fixed.
bool Recovered(const odomcal::CalibrationResult& result,
               const odomcal::SimulatedDrive& drive,
               const std::string& name) {
  if (!Check(result.status == odomcal::CalibrationStatus::kSuccess,
             name + ": " + result.message)) {
    return false;
  }
  const double rotation_error_deg =
      result.odom_from_cam.rotation.angularDistance(
          drive.odom_from_cam.rotation) *
      odomcal::kRadToDeg;
  const double xy_error_m = (result.odom_from_cam.translation.head<2>() -
                             drive.odom_from_cam.translation.head<2>())
                                .norm();
  const double scale_error =
      std::abs(result.metric_scales.at(0) / drive.metric_scale - 1.0);
  std::printf(
      "%s: rotation error %.2g deg, xy error %.2g m, scale error %.2g\n",
      name.c_str(),
      rotation_error_deg,
      xy_error_m,
      scale_error);
  return Check(rotation_error_deg < 0.1, name + ": rotation error") &&
         Check(xy_error_m < 1e-3, name + ": translation error") &&
         Check(scale_error < 1e-3, name + ": scale error");
}

// A COLMAP project of the drive's camera poses: one text sub-model
// sparse/0 (cameras, images, no points), image_timestamps.csv and the
// odometry CSV; returns the inputs of CalibrateColmapProject.
odomcal::ColmapCalibrationInputs WriteColmapProject(
    const odomcal::SimulatedDrive& drive, const std::filesystem::path& root) {
  std::filesystem::create_directories(root / "sparse" / "0");
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
  for (size_t i = 0; i < drive.camera.poses.size(); ++i) {
    odomcal::ColmapImage image;
    image.image_id = static_cast<uint32_t>(i + 1);
    image.camera_id = 1;
    image.name = "frame" + std::to_string(i) + ".png";
    image.cam_from_world =
        odomcal::Inverse(drive.camera.poses[i].world_from_sensor);
    model.images[image.image_id] = image;
    stamps << image.name << ","
           << odomcal::FormatTimestampSeconds(drive.camera.poses[i].stamp_ns)
           << "\n";
  }
  odomcal::WriteColmapModel(
      model, (root / "sparse" / "0").string(), odomcal::ColmapFormat::kText);
  odomcal::WriteOdometryCsv(drive.odometry, (root / "odometry.csv").string());
  odomcal::ColmapCalibrationInputs inputs;
  inputs.model_path = (root / "sparse").string();
  inputs.odometry_path = (root / "odometry.csv").string();
  inputs.image_timestamps_path = (root / "image_timestamps.csv").string();
  return inputs;
}

}  // namespace

int main(int argc, char** argv) {
  const std::filesystem::path folder =
      argc > 1 ? argv[1] : std::filesystem::temp_directory_path();
  // datasets: a noise-free drive with the default mount and scale.
  odomcal::DriveSimulatorOptions options;
  options.seed = 7;
  options.duration_s = 30.0;
  const odomcal::SimulatedDrive drive = odomcal::SimulateDrive(options);

  // adapters: the files the CLI reads, and the motion pairs.
  const std::string camera_path = (folder / "camera.txt").string();
  const std::string odometry_path = (folder / "odometry.csv").string();
  odomcal::WriteTumTrajectory(drive.camera, camera_path);
  odomcal::WriteOdometryCsv(drive.odometry, odometry_path);
  const odomcal::AssociationResult association =
      odomcal::AssociateCameraWithOdometry(
          {drive.camera}, drive.odometry, odomcal::AssociationOptions{});

  // solver: calibrate the pairs directly.
  const odomcal::CalibrationResult direct = odomcal::CalibrateOdomCam(
      association.pairs, odomcal::CalibrationOptions{});

  // datasets_paper: the CM baseline on the same pairs (noise-free: exact).
  const odomcal::ChangEstimate chang = odomcal::EstimateOdomFromCamChang(
      association.pairs, odomcal::CalibrationOptions{});
  odomcal::CalibrationResult chang_result;
  chang_result.status = chang.success ? odomcal::CalibrationStatus::kSuccess
                                      : odomcal::CalibrationStatus::kNotRun;
  chang_result.message = "CM failed: " + chang.failure;
  chang_result.odom_from_cam = chang.odom_from_cam;
  chang_result.metric_scales = chang.metric_scales;

  // datasets_rendering: the centre of a 4 x 3 m room is 1.5 m from a wall.
  const odomcal::RoomLayout room =
      odomcal::MakeRectangularRoom(4.0, 3.0, 2.5, true, {});
  const double wall_distance_m =
      room.DistanceToObstacles(Eigen::Vector2d(2.0, 1.5));

  // plugin: the calibration of a COLMAP project; reports: its files.
  const odomcal::ColmapCalibrationInputs project =
      WriteColmapProject(drive, folder / "project");
  const odomcal::ColmapCalibrationRun calibrated =
      odomcal::CalibrateColmapProject(project);
  const std::string output = (folder / "project_outputs").string();
  odomcal::ClaimOutputFolder(output,
                             odomcal::ColmapCalibrationOutputEntries(),
                             odomcal::ExistingOutputs::kReplaceOwn);
  // The context's default echo: the options of `project`, as the CLI's.
  const odomcal::ReportContext context =
      odomcal::ProjectReportContext(project, calibrated, "consumer");
  const std::vector<std::string> written =
      odomcal::WriteColmapCalibrationOutputs(calibrated, context, output);
  const nlohmann::json project_json =
      odomcal::ColmapCalibrationToJson(calibrated, context);

  // cli: the `odomcal calibrate` pipeline on the files, and its JSON.
  odomcal::CalibrateInputs inputs;
  inputs.camera_paths = {camera_path};
  inputs.odometry_path = odometry_path;
  const odomcal::CalibrationRun run =
      odomcal::RunCalibrationPipeline(inputs, "odomcal calibrate");
  const nlohmann::json json =
      odomcal::CalibrationToJson(run.result, run.context);

  const bool ok =
      Recovered(direct, drive, "solver") &&
      Recovered(chang_result, drive, "datasets_paper") &&
      Check(std::abs(wall_distance_m - 1.5) < 1e-12,
            "datasets_rendering: wall distance") &&
      Recovered(calibrated.check.result, drive, "plugin") &&
      Check(calibrated.metric_models.size() == 1 &&
                calibrated.metric_models[0].model.images.size() ==
                    drive.camera.poses.size(),
            "plugin: one metric sub-model with every image") &&
      Check(written.size() == 9 &&
                std::filesystem::exists(std::filesystem::path(output) /
                                        "report.html") &&
                std::filesystem::exists(std::filesystem::path(output) /
                                        "calibration.urdf"),
            "reports: calibration.json, .yaml, the four robot files, "
            "sparse_metric/, camera_in_odom.tum, report.html") &&
      Check(project_json.at("options").contains("min_inconsistent_run_pairs") &&
                project_json.at("options").contains("noise"),
            "reports: the options echo of the project") &&
      Recovered(run.result, drive, "cli") &&
      Check(json.at("status") == "success" &&
                json.at("schema") == "odomcal.calibration",
            "plugin: result JSON " + json.dump());
  return ok ? 0 : 1;
}
