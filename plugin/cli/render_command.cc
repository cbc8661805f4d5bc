#include "odomcal/plugin/cli/render_command.h"

#include "odomcal/adapters/format_error.h"
#include "odomcal/datasets/rendering/dataset_presets.h"
#include "odomcal/datasets/rendering/rendered_dataset.h"
#include "odomcal/datasets/rendering/rendered_rig.h"
#include "odomcal/datasets/rendering/rig_layout.h"
#include "odomcal/datasets/simulation/camera_mount.h"
#include "odomcal/plugin/cli/calibrate_command.h"
#include "odomcal/plugin/cli/command_line.h"
#include "odomcal/plugin/output/output_file.h"
#include "odomcal/plugin/output/output_folder.h"
#include "odomcal/solver/format_number.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <optional>
#include <regex>
#include <string>
#include <vector>

namespace odomcal {
namespace {

// The camera at `size` ("WIDTHxHEIGHT") pixels: the focal lengths and the
// principal point scaled with the width (the horizontal field of view and
// square pixels kept), the principal point's vertical place relative to the
// height kept. Throws std::invalid_argument naming the flag.
CameraIntrinsics ResizedCamera(const CameraIntrinsics& camera,
                               const std::string& size) {
  int width = 0;
  int height = 0;
  char x = 0;
  char rest = 0;
  if (std::sscanf(size.c_str(), "%d%c%d%c", &width, &x, &height, &rest) != 3 ||
      x != 'x' || width < 64 || height < 64 || width > 8192 || height > 8192) {
    throw std::invalid_argument("--image_size: '" + size +
                                "' is not WIDTHxHEIGHT with each 64 to 8192");
  }
  CameraIntrinsics resized = camera;
  const double scale = static_cast<double>(width) / camera.width;
  resized.width = width;
  resized.height = height;
  resized.fx = camera.fx * scale;
  resized.fy = camera.fy * scale;
  resized.cx = camera.cx * scale;
  resized.cy = camera.cy / camera.height * height;
  try {
    resized.Check();
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument("--image_size " + size + ": " + error.what());
  }
  return resized;
}

namespace fs = std::filesystem;

// Refuses a non-empty output folder unless overwriting; then removes the
// images an earlier render left (only names this command writes, in the
// images/ odomcal wrote: output_folder.h): a single camera's NNNNNN.png and
// a rig's <camera>/<stamp>.png, a camera's folder left empty and, for a
// single camera, a rig's cameras.txt. Stale camera folders would otherwise
// be read with the new images (COLMAP reads images/ recursively).
void PrepareOutputFolder(const fs::path& dir, bool overwrite, bool rig) {
  std::vector<std::string> entries = {"images",
                                      "odometry.csv",
                                      "odometry_ground_truth.csv",
                                      "odometry_se3.tum",
                                      "image_timestamps.csv",
                                      "ground_truth.json"};
  if (rig) entries.push_back("cameras.txt");
  ClaimOutputFolder(dir.string(),
                    entries,
                    overwrite ? ExistingOutputs::kReplaceOwn
                              : ExistingOutputs::kRefuseNonEmptyFolder);
  std::error_code error;
  if (!rig && fs::exists(dir / "cameras.txt", error)) {
    // A rig's, which would not describe this dataset; a cameras.txt of the
    // user's (not in the record) stays.
    try {
      RemoveOwnedOutput(dir.string(), "cameras.txt");
    } catch (const OutputError&) {
    }
  }
  const fs::path images = dir / "images";
  if (!fs::is_directory(images, error)) return;
  static const std::regex kImageName("[0-9]{6}\\.png");
  static const std::regex kRigImageName("[0-9]{19}\\.png");
  for (const fs::directory_entry& entry : fs::directory_iterator(images)) {
    const std::string name = entry.path().filename().string();
    if (std::regex_match(name, kImageName)) {
      RemoveOwnedOutput(dir.string(), "images/" + name);
    } else if (entry.is_directory(error)) {
      for (const fs::directory_entry& image :
           fs::directory_iterator(entry.path())) {
        const std::string image_name = image.path().filename().string();
        if (std::regex_match(image_name, kRigImageName)) {
          RemoveOwnedOutput(dir.string(), "images/" + name + "/" + image_name);
        }
      }
      if (fs::is_empty(entry.path(), error)) {
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

std::string RigHelp() {
  std::string text =
      "render a multi-camera rig instead of the preset's camera: one folder "
      "per camera in images/, cameras.txt, and the cameras in "
      "ground_truth.json:";
  for (const RigLayoutInfo& info : RigLayouts()) {
    text += "\n  " + info.name + ": " + info.summary;
  }
  return text;
}

// Renders and writes a rig's dataset with the progress lines of a single
// camera's; the cameras' image counts after the scene's line.
int RenderRig(const RenderedDatasetOptions& options,
              const RigLayout& layout,
              uint64_t seed,
              const std::string& output_path,
              const std::function<double()>& elapsed) {
  std::cout << "odomcal render: preset " << options.preset << ", rig "
            << layout.name << ", seed " << seed << ", " << options.num_images
            << " images of the reference camera " << layout.cameras.front().name
            << " -> " << output_path << "\n";
  const RenderedRig rig = SimulateRenderedRig(options, layout);
  std::printf("  scene: %zu surfaces, path %.1f s (%.1f s)\n",
              rig.drive.scene.surfaces.size(),
              1e-9 * rig.drive.path.duration_ns(),
              elapsed());
  for (const RenderedRigCamera& camera : rig.cameras) {
    std::printf("  camera %s: %zu images %dx%d at %g Hz, phase %g s%s\n",
                camera.camera.name.c_str(),
                camera.frames.size(),
                camera.camera.intrinsics->width,
                camera.camera.intrinsics->height,
                *camera.camera.rate_hz,
                camera.camera.phase_s,
                camera.camera.capped ? ", capped" : "");
  }
  std::fflush(stdout);
  WriteRenderedRig(rig, output_path, [&](size_t done, size_t total) {
    if (done == total || done % std::max<size_t>(1, total / 10) == 0) {
      std::printf(
          "  rendered %zu/%zu images (%.1f s)\n", done, total, elapsed());
      std::fflush(stdout);
    }
  });
  std::printf(
      "odomcal render: wrote %s in %.1f s\n", output_path.c_str(), elapsed());
  return kExitSuccess;
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
                 "also odometry_se3.tum; --rig: images/<camera>/ and "
                 "cameras.txt)")
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
                 "is as long as they take at the preset's camera rate); with "
                 "--rig the reference (first) camera's, at its rate, the "
                 "others' follow from their rates (without it a rig keeps "
                 "the preset's drive length)")
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
  std::string image_size;
  app.add_option("--image_size",
                 image_size,
                 "WIDTHxHEIGHT pixels instead of the preset's (e.g. 1280x720): "
                 "the horizontal field of view kept, square pixels, the "
                 "principal point at the same relative place");
  double odometry_rate_hz = 0.0;
  app.add_option("--odometry_rate_hz",
                 odometry_rate_hz,
                 "the wheel odometry's rate instead of the preset's 50 Hz "
                 "(at least the camera's rate): a low-rate log")
      ->check(CLI::Range(0.5, 1000.0));
  std::string texture = "dense";
  app.add_option("--texture",
                 texture,
                 "room presets: dense (the preset's: 6 mm texels, detail "
                 "from 1.2 cm), sparse (18 mm texels, detail from 14 cm: "
                 "fewer features), repetitive (one 19 cm tile repeated on "
                 "every surface)")
      ->check(CLI::IsMember({"dense", "sparse", "repetitive"}));
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
  std::string rig_name;
  std::vector<std::string> rig_names;
  for (const RigLayoutInfo& info : RigLayouts()) rig_names.push_back(info.name);
  app.add_option("--rig", rig_name, RigHelp())->check(CLI::IsMember(rig_names));
  std::vector<std::string> capped_cameras;
  app.add_option("--capped_camera",
                 capped_cameras,
                 "with --rig: a lens cap on this camera (repeatable): its "
                 "images are uniformly dark, nothing COLMAP can match");
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
    if (options.road &&
        (floor_slope_deg != 0.0 || untextured_floor || texture != "dense")) {
      throw std::invalid_argument(
          "--floor_slope_deg, --untextured_floor and --texture apply to the "
          "room presets, not to '" +
          preset + "'");
    }
    if (odometry_rate_hz > 0.0) {
      if (odometry_rate_hz < options.camera_rate_hz) {
        throw std::invalid_argument(
            "--odometry_rate_hz " + FormatNumber(odometry_rate_hz) +
            " is below the camera's rate of the preset (" +
            FormatNumber(options.camera_rate_hz) + " Hz)");
      }
      options.odometry_rate_hz = odometry_rate_hz;
    }
    if (texture == "sparse") {
      options.scene.texel_size_m = 0.018;
      options.scene.min_period_texels = 8;
    } else if (texture == "repetitive") {
      options.scene.repeat_period_texels = 32;
    }
    if (!image_size.empty()) {
      if (!rig_name.empty()) {
        throw std::invalid_argument(
            "--image_size sets the single camera's size; --rig " + rig_name +
            " has its own cameras: drop one of the two");
      }
      options.camera = ResizedCamera(options.camera, image_size);
    }
    std::optional<RigLayout> rig;
    if (!rig_name.empty()) {
      if (!camera_mount.empty()) {
        throw std::invalid_argument(
            "--camera_mount sets the single camera's mount; --rig " + rig_name +
            " has its own mounts: drop one of the two");
      }
      rig = MakeRigLayout(rig_name);
      for (const std::string& name : capped_cameras) {
        try {
          rig->Camera(name).capped = true;
        } catch (const std::invalid_argument& error) {
          throw std::invalid_argument(std::string("--capped_camera: ") +
                                      error.what());
        }
      }
    } else if (!capped_cameras.empty()) {
      throw std::invalid_argument(
          "--capped_camera caps a camera of a rig: it needs --rig");
    }
    PrepareOutputFolder(output_path, overwrite, rig.has_value());
    // A rig keeps the preset's drive length unless told the reference
    // camera's number of images.
    if (num_images > 0) {
      options.num_images = num_images;
    } else if (rig) {
      options.num_images = RigReferenceImageCount(options, *rig);
    }
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
    if (rig) {
      return RenderRig(options, *rig, seed, output_path, elapsed);
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
