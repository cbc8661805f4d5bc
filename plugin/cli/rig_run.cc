#include "odomcal/plugin/cli/rig_run.h"

#include "odomcal/adapters/format_error.h"
#include "odomcal/plugin/cli/colmap_rig_outputs.h"
#include "odomcal/plugin/cli/command_flags.h"
#include "odomcal/plugin/cli/command_line.h"
#include "odomcal/plugin/cli/rig_calibration.h"
#include "odomcal/plugin/cli/rig_report.h"
#include "odomcal/plugin/cli/run_command.h"
#include "odomcal/plugin/colmap/colmap_runner.h"
#include "odomcal/plugin/output/output_folder.h"
#include "odomcal/plugin/report/colmap_calibration_outputs.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <set>
#include <stdexcept>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

}  // namespace

std::vector<std::string> RigCameraFolders(const std::string& image_path) {
  std::set<std::string> folders;
  for (const auto& entry : fs::recursive_directory_iterator(image_path)) {
    if (!entry.is_regular_file() || !IsImageFile(entry.path())) continue;
    const fs::path relative = fs::relative(entry.path(), image_path);
    if (!relative.has_parent_path()) {
      throw std::invalid_argument(
          "--rig: " + entry.path().string() +
          " lies in no camera sub-folder of --image_path (with --rig, each "
          "sub-folder is one camera: images/front/..., images/rear/...)");
    }
    folders.insert(relative.begin()->string());
  }
  if (folders.empty()) {
    throw std::invalid_argument("--rig: no sub-folder of " + image_path +
                                " holds images (.png, .jpg, .jpeg, .bmp, "
                                ".tif)");
  }
  // A camera folder without images is a camera that recorded nothing (or a
  // wrong path): said, not skipped.
  for (const auto& entry : fs::directory_iterator(image_path)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_directory() && folders.count(name) == 0) {
      throw std::invalid_argument("--rig: camera sub-folder " +
                                  entry.path().string() +
                                  " holds no images (.png, .jpg, .jpeg, "
                                  ".bmp, .tif)");
    }
  }
  for (const std::string& folder : folders) {
    CheckCameraName(folder, "--rig: camera sub-folder '" + folder + "'");
  }
  return {folders.begin(), folders.end()};
}

std::map<std::string, std::string> RigCameraParams(
    const std::vector<std::string>& values,
    const std::vector<std::string>& cameras,
    const std::string& cameras_from) {
  const bool for_every_camera =
      std::any_of(values.begin(), values.end(), [](const std::string& value) {
        return value.find('=') == std::string::npos;
      });
  if (for_every_camera && values.size() > 1) {
    throw std::invalid_argument(
        "--camera_params: give either one PARAMS for every camera or "
        "NAME=PARAMS per camera, not both");
  }
  std::map<std::string, std::string> params;
  for (const std::string& value : values) {
    const size_t equals = value.find('=');
    if (equals == std::string::npos) {
      for (const std::string& camera : cameras) params[camera] = value;
      continue;
    }
    const std::string name = value.substr(0, equals);
    if (std::find(cameras.begin(), cameras.end(), name) == cameras.end()) {
      throw std::invalid_argument("--camera_params '" + value +
                                  "': no camera '" + name +
                                  "' (the cameras of " + cameras_from + ": " +
                                  JoinNames(cameras) + ")");
    }
    if (!params.emplace(name, value.substr(equals + 1)).second) {
      throw std::invalid_argument("--camera_params '" + value + "': camera '" +
                                  name + "' given twice");
    }
  }
  return params;
}

int RunRigReconstruction(
    const ReconstructionOptions& run,
    const std::vector<std::string>& camera_params,
    const std::string& reference_camera,
    const nlohmann::json& bag_echo,
    const std::map<std::string, std::string>& camera_models) {
  run.project.Check();
  const std::vector<std::string> names = RigCameraFolders(run.image_path);
  const std::map<std::string, std::string> params =
      RigCameraParams(camera_params, names);
  int reference = 0;
  if (!reference_camera.empty()) {
    const auto it = std::find(names.begin(), names.end(), reference_camera);
    if (it == names.end()) {
      throw std::invalid_argument("--reference_camera '" + reference_camera +
                                  "' names no camera sub-folder of "
                                  "--image_path (its cameras: " +
                                  JoinNames(names) + ")");
    }
    reference = static_cast<int>(it - names.begin());
  }
  PrepareOutputFolder({run.workspace_path, "--workspace_path"},
                      UserInputs(run),
                      ColmapCalibrationOutputEntries(),
                      ExistingOutputs::kReplaceOwn);
  std::cout << "cameras: " << names.size() << " (one per sub-folder of "
            << run.image_path << "): " << JoinNames(names) << "\n"
            << std::flush;

  ColmapRigRun rig;
  rig.grouping = ColmapCameraGrouping::kBySubFolder;
  rig.reference = reference;
  RigCalibrationRun as_rig;
  as_rig.reference = reference;
  for (size_t k = 0; k < names.size(); ++k) {
    const std::string& name = names[k];
    std::cout << "camera " << name << " (" << k + 1 << " of " << names.size()
              << "), in "
              << (fs::path(run.workspace_path) / "cameras" / name).string()
              << ":\n"
              << std::flush;
    ReconstructionOptions camera_options = run;
    camera_options.image_sub_folder = name;
    camera_options.workspace_path =
        (fs::path(run.workspace_path) / "cameras" / name).string();
    const auto given = params.find(name);
    camera_options.camera_params =
        given == params.end() ? std::string() : given->second;
    const auto model = camera_models.find(name);
    if (model != camera_models.end())
      camera_options.camera_model = model->second;

    ColmapRigCameraRun camera_run;
    camera_run.camera.name = name;
    camera_run.inputs = run.project;
    RigCameraRun summary;
    summary.name = name;
    try {
      const RunOutcome outcome =
          RunAndWriteOutputs(camera_options, "odomcal run", bag_echo);
      camera_run.run = outcome.calibration;
      camera_run.inputs.model_path = outcome.context.camera_paths.empty()
                                         ? std::string()
                                         : outcome.context.camera_paths[0];
      for (const ColmapSegment& segment : outcome.calibration.segments) {
        camera_run.camera.num_images += segment.num_registered_images;
      }
      summary.run = {outcome.calibration.check.result, outcome.context};
    } catch (const ColmapError& error) {
      camera_run.input_error = error.what();
      camera_run.failure_status = summary.failure_status = "colmap_failed";
    } catch (const FormatError& error) {
      camera_run.input_error = error.what();
    }
    if (!camera_run.input_error.empty()) {
      std::cout << "  camera " << name << ": " << camera_run.input_error
                << "\n";
      summary.input_error = camera_run.input_error;
      summary.run.result.message = camera_run.input_error;
      summary.run.context.command = "odomcal run";
      summary.run.context.robot_frames = run.project.robot_frames;
      summary.run.context.odometry_path = run.project.odometry_path;
    }
    summary.extrinsic = ExtrinsicOf(summary.run.result);
    rig.cameras.push_back(std::move(camera_run));
    as_rig.cameras.push_back(std::move(summary));
  }
  if (run.project.joint_adjustment.use != JointAdjustmentUse::kOff &&
      as_rig.NumCalibrated() > 1) {
    std::cout << (run.project.joint_adjustment.use == JointAdjustmentUse::kOn
                      ? "rig joint adjustment"
                      : "rig joint adjustment check")
              << " of the calibrated cameras ...\n"
              << std::flush;
  }
  // A rig's adjustment of thousands of images takes minutes: where it is,
  // every 10 s.
  auto last_line = std::chrono::steady_clock::now();
  AdjustColmapRigJointly(
      run.project,
      [&](const std::string& message) {
        const auto now = std::chrono::steady_clock::now();
        if (now - last_line < std::chrono::seconds(10)) return;
        last_line = now;
        std::cout << "  " << message << "\n" << std::flush;
      },
      &rig);
  AdoptRigJointAdjustment(rig.joint, run.project.calibration, &as_rig);
  const std::vector<std::string> written = WriteColmapRigOutputs(
      rig, as_rig, run.workspace_path, /*write_camera_folders=*/false);
  std::cout << RigCalibrationSummary(as_rig);
  std::cout << "  wrote " << run.workspace_path << "/{" << JoinNames(written)
            << "}\n";
  if (as_rig.NumCalibrated() > 0) {
    std::cout << std::flush;
    for (const std::string& warning : as_rig.Warnings()) {
      std::cerr << "odomcal run: warning: " << warning << "\n";
    }
  }
  return RigExitCode(as_rig);
}

}  // namespace odomcal
