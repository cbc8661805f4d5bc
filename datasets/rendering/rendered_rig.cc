// A rig's dataset: the reference camera's single-camera dataset gives the
// drive (path, odometry, scene); every camera then takes its frames at its
// own rate and phase inside the reference's frames, posed by the robot's
// true pose at each capture. Writing renders camera by camera; a capped
// camera's images are filled without ray casting.

#include "odomcal/datasets/rendering/rendered_rig.h"

#include "odomcal/adapters/timestamp.h"
#include "odomcal/datasets/rendering/rendered_files_internal.h"
#include "odomcal/datasets/simulation/seed.h"

#include <nlohmann/json.hpp>

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <stdexcept>

namespace odomcal {
namespace {

// The fewest digits (15 to 17) that read back as the same double.
std::string RoundTripNumber(double value) {
  char text[32];
  for (int digits = 15; digits <= 17; ++digits) {
    std::snprintf(text, sizeof(text), "%.*g", digits, value);
    if (std::strtod(text, nullptr) == value) break;
  }
  return text;
}

// The camera with the preset's intrinsics and rate where the layout has
// none.
RigCamera Resolved(const RigCamera& camera,
                   const RenderedDatasetOptions& options) {
  RigCamera resolved = camera;
  resolved.intrinsics = camera.intrinsics.value_or(options.camera);
  resolved.rate_hz = camera.rate_hz.value_or(options.camera_rate_hz);
  return resolved;
}

}  // namespace

int RigReferenceImageCount(const RenderedDatasetOptions& options,
                           const RigLayout& rig) {
  rig.Check();
  const double rate =
      rig.cameras.front().rate_hz.value_or(options.camera_rate_hz);
  return 1 + static_cast<int>(std::lround((options.num_images - 1) * rate /
                                          options.camera_rate_hz));
}

RenderedRig SimulateRigMotion(const RenderedDatasetOptions& options,
                              const RigLayout& rig) {
  rig.Check();
  RenderedRig result;
  result.name = rig.name;
  for (const RigCamera& camera : rig.cameras) {
    RenderedRigCamera rendered;
    rendered.camera = Resolved(camera, options);
    rendered.camera_time_offset_s =
        options.camera_time_offset_s + camera.time_offset_s;
    result.cameras.push_back(rendered);
  }

  const RigCamera& reference = result.cameras.front().camera;
  RenderedDatasetOptions drive = options;
  drive.camera = *reference.intrinsics;
  drive.odom_from_cam = reference.odom_from_cam;
  drive.camera_rate_hz = *reference.rate_hz;
  drive.camera_time_offset_s = result.cameras.front().camera_time_offset_s;
  result.drive = SimulateDatasetMotion(drive);
  const RenderedDatasetOptions& o = result.drive.options;
  const int64_t last_capture_ns =
      result.drive.frames.back().capture_ns - o.start_stamp_ns;
  const Rigid3d origin_from_room = Inverse(result.drive.room_from_origin);

  for (size_t c = 0; c < result.cameras.size(); ++c) {
    RenderedRigCamera& rendered = result.cameras[c];
    const RigCamera& camera = rendered.camera;
    const double rate_hz = *camera.rate_hz;
    const std::string where = "rig camera '" + camera.name + "': ";
    if (rate_hz > o.odometry_rate_hz) {
      throw std::invalid_argument(where + "rate_hz above odometry_rate_hz");
    }
    if (o.camera_time_jitter_s * rate_hz > 0.05) {
      throw std::invalid_argument(where +
                                  "camera_time_jitter_s above 0.05 / rate_hz");
    }
    // The reference's stream is SimulateDatasetMotion's: its frames are the
    // single-camera dataset's.
    std::mt19937_64 jitter_rng(DeriveSeed(o.seed, c == 0 ? 4 : 100 + c));
    std::normal_distribution<double> jitter(0.0, o.camera_time_jitter_s);
    for (int k = 0;; ++k) {
      const int64_t capture_ns =
          SecondsToNs(o.lead_time_s + camera.phase_s + k / rate_hz);
      if (capture_ns > last_capture_ns) break;
      RenderedFrame frame;
      frame.capture_ns = o.start_stamp_ns + capture_ns;
      const double noise_s =
          o.camera_time_jitter_s > 0.0 ? jitter(jitter_rng) : 0.0;
      frame.stamp_ns = frame.capture_ns +
                       SecondsToNs(rendered.camera_time_offset_s + noise_s);
      if (frame.stamp_ns < 0) {
        throw std::invalid_argument(where + "a negative time stamp");
      }
      if (!rendered.frames.empty() &&
          frame.stamp_ns <= rendered.frames.back().stamp_ns) {
        throw std::invalid_argument(where + "time stamps out of order");
      }
      char name[32];
      std::snprintf(name, sizeof(name), "%019" PRId64 ".png", frame.stamp_ns);
      frame.image_name = camera.name + "/" + name;
      frame.room_from_cam =
          RoomFromOdomAt(result.drive, capture_ns) * camera.odom_from_cam;
      frame.origin_from_cam = origin_from_room * frame.room_from_cam;
      rendered.frames.push_back(frame);
    }
    if (rendered.frames.size() < 2) {
      char span[64];
      std::snprintf(span,
                    sizeof(span),
                    "%.3f s",
                    1e-9 * (last_capture_ns - SecondsToNs(o.lead_time_s)));
      throw std::invalid_argument(where +
                                  "fewer than 2 frames in the drive's " + span +
                                  " of images (phase_s too late or rate_hz "
                                  "too low)");
    }
  }
  result.drive.frames = result.cameras.front().frames;
  return result;
}

RenderedRig SimulateRenderedRig(const RenderedDatasetOptions& options,
                                const RigLayout& rig) {
  RenderedRig result = SimulateRigMotion(options, rig);
  const RenderedDatasetOptions& o = result.drive.options;
  result.drive.scene = o.road ? BuildRoadScene(*o.road, o.scene)
                              : BuildRoomScene(o.layout, o.scene);
  return result;
}

Image RenderRigFrame(const RenderedRig& rig, size_t camera, size_t index) {
  if (camera >= rig.cameras.size() ||
      index >= rig.cameras[camera].frames.size()) {
    throw std::invalid_argument("RenderRigFrame: index out of range");
  }
  const RenderedRigCamera& rendered = rig.cameras[camera];
  const CameraIntrinsics& intrinsics = *rendered.camera.intrinsics;
  if (rendered.camera.capped) {
    Image image;
    image.width = intrinsics.width;
    image.height = intrinsics.height;
    image.rgb.assign(static_cast<size_t>(image.width) * image.height * 3,
                     kCappedImageValue);
    return image;
  }
  return RenderImage(rig.drive.scene,
                     intrinsics,
                     rendered.frames[index].room_from_cam,
                     rig.drive.options.render);
}

std::string RigGroundTruthJson(const RenderedRig& rig) {
  nlohmann::json truth = nlohmann::json::parse(GroundTruthJson(rig.drive));
  nlohmann::json cameras = nlohmann::json::array();
  for (size_t c = 0; c < rig.cameras.size(); ++c) {
    const RenderedRigCamera& rendered = rig.cameras[c];
    const RigCamera& camera = rendered.camera;
    nlohmann::json images = nlohmann::json::array();
    for (const RenderedFrame& frame : rendered.frames) {
      images.push_back(internal::FrameJson(frame));
    }
    cameras.push_back(
        {{"name", camera.name},
         {"camera_id", c + 1},
         {"image_prefix", camera.name + "/"},
         {"reference", c == 0},
         {"capped", camera.capped},
         {"odom_from_cam", internal::TransformJson(camera.odom_from_cam)},
         {"cam_from_odom",
          internal::TransformJson(Inverse(camera.odom_from_cam))},
         {"camera", internal::IntrinsicsJson(*camera.intrinsics)},
         {"rate_hz", *camera.rate_hz},
         {"phase_s", camera.phase_s},
         {"camera_time_offset_s", rendered.camera_time_offset_s},
         {"num_images", rendered.frames.size()},
         {"images", images}});
  }
  truth["cameras"] = cameras;
  truth["rig"] = {
      {"name", rig.name},
      {"reference_camera", rig.cameras.front().camera.name},
      {"image_layout",
       "images/<name>/<recorded stamp in ns>.png, one folder per camera "
       "(COLMAP's rig layout): images of synchronised cameras share names "
       "(one COLMAP frame), no others do"},
      {"note",
       "the top-level odom_from_cam, cam_from_odom, camera, timing and images "
       "are the reference camera's; capture_k = lead + phase_s + k / rate_hz "
       "up to the reference camera's last capture"}};
  return truth.dump(2) + "\n";
}

std::string RigCamerasText(const RenderedRig& rig) {
  std::string text =
      "# Camera list with one line of data per camera:\n"
      "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
      "# Number of cameras: " +
      std::to_string(rig.cameras.size()) + "\n";
  for (size_t c = 0; c < rig.cameras.size(); ++c) {
    const RigCamera& camera = rig.cameras[c].camera;
    const CameraIntrinsics& intrinsics = *camera.intrinsics;
    std::string line = std::to_string(c + 1) + " " +
                       intrinsics.ColmapModelName() + " " +
                       std::to_string(intrinsics.width) + " " +
                       std::to_string(intrinsics.height);
    std::string params;
    for (const double value : intrinsics.ColmapParams()) {
      line += " " + RoundTripNumber(value);
      params += (params.empty() ? "" : ",") + RoundTripNumber(value);
    }
    text += "# " + camera.name + " (images/" + camera.name +
            "/): odomcal run --camera_model " + intrinsics.ColmapModelName() +
            " --camera_params " + params + "\n" + line + "\n";
  }
  return text;
}

void WriteRenderedRig(
    const RenderedRig& rig,
    const std::string& output_dir,
    const std::function<void(size_t done, size_t total)>& progress) {
  namespace fs = std::filesystem;
  const fs::path root(output_dir);
  size_t total = 0;
  for (const RenderedRigCamera& camera : rig.cameras) {
    const fs::path folder = root / "images" / camera.camera.name;
    std::error_code error;
    fs::create_directories(folder, error);
    if (error || !fs::is_directory(folder)) {
      throw std::runtime_error(folder.string() + ": cannot create the folder");
    }
    total += camera.frames.size();
  }
  std::string timestamps = "image_name,timestamp\n";
  size_t done = 0;
  for (size_t c = 0; c < rig.cameras.size(); ++c) {
    for (size_t i = 0; i < rig.cameras[c].frames.size(); ++i) {
      const RenderedFrame& frame = rig.cameras[c].frames[i];
      internal::WritePng(RenderRigFrame(rig, c, i),
                         (root / "images" / frame.image_name).string());
      timestamps += frame.image_name + "," +
                    FormatTimestampSeconds(frame.stamp_ns) + "\n";
      if (progress) progress(++done, total);
    }
  }
  internal::WriteOdometryFiles(rig.drive, output_dir);
  internal::WriteTextFile((root / "image_timestamps.csv").string(), timestamps);
  internal::WriteTextFile((root / "cameras.txt").string(), RigCamerasText(rig));
  internal::WriteTextFile((root / "ground_truth.json").string(),
                          RigGroundTruthJson(rig));
}

}  // namespace odomcal
