#include "odomcal/plugin/cli/render_command.h"

#include "odomcal/adapters/format_error.h"
#include "odomcal/datasets/rendering/dataset_presets.h"
#include "odomcal/datasets/rendering/rendered_dataset.h"
#include "odomcal/datasets/simulation/camera_mount.h"
#include "odomcal/plugin/cli/calibrate_command.h"
#include "odomcal/plugin/cli/command_line.h"
#include "odomcal/plugin/output/output_file.h"
#include "odomcal/plugin/output/output_folder.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <regex>
#include <string>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

// Refuses a non-empty output folder unless overwriting; then removes the
// images an earlier render left (only names this command writes, in the
// images/ odomcal wrote: output_folder.h).
void PrepareOutputFolder(const fs::path& dir, bool overwrite) {
  ClaimOutputFolder(dir.string(),
                    {"images",
                     "odometry.csv",
                     "odometry_ground_truth.csv",
                     "odometry_se3.tum",
                     "image_timestamps.csv",
                     "ground_truth.json"},
                    overwrite ? ExistingOutputs::kReplaceOwn
                              : ExistingOutputs::kRefuseNonEmptyFolder);
  std::error_code error;
  const fs::path images = dir / "images";
  if (fs::is_directory(images, error)) {
    static const std::regex kImageName("[0-9]{6}\\.png");
    for (const fs::directory_entry& entry : fs::directory_iterator(images)) {
      const std::string name = entry.path().filename().string();
      if (std::regex_match(name, kImageName)) {
        RemoveOwnedOutput(dir.string(), "images/" + name);
      }
    }
  }
}

std::string PresetHelp() {
  std::string text = "dataset preset:";
  for (const DatasetPresetInfo& info : DatasetPresets()) {
    text += "\n  " + info.name + ": " + info.summary;
  }
  return text;
}

}  // namespace

int RunRender(int argc, char** argv) {
  CLI::App app{
      "Renders a synthetic calibration dataset: a camera on a wheeled robot "
      "driving through a textured room (or a car on a road), with wheel "
      "odometry and ground truth.",
      "odomcal render"};
  std::string preset;
  std::string output_path;
  uint64_t seed = 1;
  bool overwrite = false;
  std::vector<std::string> names;
  for (const DatasetPresetInfo& info : DatasetPresets())
    names.push_back(info.name);
  app.add_option("--preset", preset, PresetHelp())
      ->required()
      ->check(CLI::IsMember(names));
  app.add_option("--output_path",
                 output_path,
                 "dataset folder: images/, odometry.csv, image_timestamps.csv, "
                 "ground_truth.json, odometry_ground_truth.csv (road presets: "
                 "also odometry_se3.tum)")
      ->required();
  app.add_option("--seed", seed, "random seed (scene textures, path, noise)")
      ->check(AtLeast(0))
      ->capture_default_str();
  app.add_flag(
      "--overwrite", overwrite, "replace a dataset already in output_path");
  int num_images = 0;
  app.add_option("--num_images",
                 num_images,
                 "images to render instead of the preset's number (the drive "
                 "is as long as they take at the preset's camera rate)")
      ->check(CLI::Range(2, 100000));
  double floor_slope_deg = 0.0;
  app.add_option("--floor_slope_deg",
                 floor_slope_deg,
                 "tilt the floor by this against the plane the robot drives "
                 "in (about the y axis through the path's start): a scene "
                 "for the floor-plane check")
      ->check(CLI::Range(-29.0, 29.0));
  bool untextured_floor = false;
  app.add_flag("--untextured_floor",
               untextured_floor,
               "a flat-coloured floor, without features: a scene whose "
               "floor COLMAP cannot see");
  std::vector<double> camera_mount;
  app.add_option("--camera_mount",
                 camera_mount,
                 "the camera's mount instead of the preset's: "
                 "YAW,PITCH_DOWN,ROLL,X,Y,Z (degrees: yaw 90 looks to the "
                 "left, pitch down towards the floor, roll about the optical "
                 "axis; metres in the odometry frame, Z the height above the "
                 "floor)")
      ->delimiter(',')
      ->expected(6);
  if (const auto exit_code = ParseFlags(&app, argc, argv)) {
    return *exit_code;
  }

  try {
    using Clock = std::chrono::steady_clock;
    const Clock::time_point start = Clock::now();
    const auto elapsed = [&] {
      return std::chrono::duration<double>(Clock::now() - start).count();
    };
    RenderedDatasetOptions options = MakeDatasetPreset(preset, seed);
    if (options.road && (floor_slope_deg != 0.0 || untextured_floor)) {
      throw std::invalid_argument(
          "--floor_slope_deg and --untextured_floor apply to the room "
          "presets, not to '" +
          preset + "'");
    }
    PrepareOutputFolder(output_path, overwrite);
    if (num_images > 0) options.num_images = num_images;
    if (!camera_mount.empty()) {
      for (const double value : camera_mount) {
        if (!std::isfinite(value)) {
          throw std::invalid_argument(
              "--camera_mount must be six finite numbers");
        }
      }
      options.odom_from_cam = MakeCameraMount(
          camera_mount[0],
          camera_mount[1],
          camera_mount[2],
          Eigen::Vector3d(camera_mount[3], camera_mount[4], camera_mount[5]));
    }
    options.layout.floor_slope_deg = floor_slope_deg;
    options.layout.floor_slope_pivot_x_m = options.path.start.x;
    for (FloorPatch& floor : options.layout.floors) {
      floor.textured = floor.textured && !untextured_floor;
    }
    std::cout << "odomcal render: preset " << preset << ", seed " << seed
              << ", " << options.num_images << " images "
              << options.camera.width << "x" << options.camera.height << " -> "
              << output_path << "\n";
    const RenderedDataset dataset = SimulateRenderedDataset(options);
    std::printf("  scene: %zu surfaces, path %.1f s (%.1f s)\n",
                dataset.scene.surfaces.size(),
                1e-9 * dataset.path.duration_ns(),
                elapsed());
    std::fflush(stdout);
    WriteRenderedDataset(dataset, output_path, [&](size_t done, size_t total) {
      // One line per 10 %, so logs stay short.
      if (done == total || done % std::max<size_t>(1, total / 10) == 0) {
        std::printf(
            "  rendered %zu/%zu images (%.1f s)\n", done, total, elapsed());
        std::fflush(stdout);
      }
    });
    std::printf(
        "odomcal render: wrote %s in %.1f s\n", output_path.c_str(), elapsed());
    return kExitSuccess;
  } catch (const OutputError& error) {
    std::cerr << "odomcal render: error: " << error.what() << "\n";
  } catch (const FormatError& error) {
    std::cerr << "odomcal render: error: " << error.what() << "\n";
  } catch (const std::invalid_argument& error) {
    std::cerr << "odomcal render: error: " << error.what() << "\n";
  } catch (const std::runtime_error& error) {
    std::cerr << "odomcal render: error: " << error.what() << "\n";
  }
  return kExitBadInput;
}

}  // namespace odomcal
