// A rendered dataset of a multi-camera rig (rig_layout.h): one drive, one
// wheel odometry, one scene, and every camera rendered at its own times
// from it.
//
// The drive is the reference camera's single-camera dataset
// (rendered_dataset.h) for the options with the reference's mount,
// intrinsics, rate and clock offset: the same path, odometry, scene and
// timeline (options.num_images is the reference camera's count; the path
// planner's clearances and view depth use its mount). Camera c captures at
// path times
//   capture_k = lead_time_s + phase_s + k / rate_hz,  k = 0, 1, ...
// up to the reference's last capture, at the robot's true pose then:
//   room_from_cam = RoomFromOdomAt(capture_k) * odom_from_cam_c.
// Its recorded stamps add options.camera_time_offset_s, its own
// time_offset_s and its own jitter stream (options.camera_time_jitter_s; the
// reference's stream is the single-camera dataset's). Image names are
// "<name>/<recorded stamp in ns, 19 digits>.png", one folder per camera as
// in COLMAP's rig layout, which groups images of one name into one frame:
// synchronised cameras (same rate, phase and clock) share names, others
// do not.
#pragma once

#include "odomcal/datasets/rendering/ray_caster.h"
#include "odomcal/datasets/rendering/rendered_dataset.h"
#include "odomcal/datasets/rendering/rig_layout.h"

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace odomcal {

struct RenderedRigCamera {
  // As in the layout, with intrinsics and rate_hz filled in from the preset
  // when the layout left them out.
  RigCamera camera;
  double camera_time_offset_s = 0.0;  // the preset's plus the camera's own
  std::vector<RenderedFrame> frames;  // in time order
};

struct RenderedRig {
  std::string name;  // the layout's
  // The reference camera's dataset; its frames are cameras[0].frames.
  RenderedDataset drive;
  std::vector<RenderedRigCamera> cameras;  // in the layout's order
};

// The reference camera's number of images that keeps the preset's drive as
// long as its own images took: 1 + round((num_images - 1) * reference rate /
// camera_rate_hz). Throws std::invalid_argument for an invalid layout.
int RigReferenceImageCount(const RenderedDatasetOptions& options,
                           const RigLayout& rig);

// Plans the drive and places every camera's frames (no scene, no pixels).
// Throws std::invalid_argument for bad options or layout, a camera faster
// than the odometry, jitter above 0.05 of a camera's period, a camera with
// fewer than 2 frames in the drive or a negative stamp; std::runtime_error
// when the path cannot be planned.
RenderedRig SimulateRigMotion(const RenderedDatasetOptions& options,
                              const RigLayout& rig);

// SimulateRigMotion plus the textured scene: ready to render.
RenderedRig SimulateRenderedRig(const RenderedDatasetOptions& options,
                                const RigLayout& rig);

// Pixel value of every channel of a capped camera's images: a lens cap lets
// almost no light in.
inline constexpr uint8_t kCappedImageValue = 4;

// Frame `index` of camera `camera` (a capped camera's: uniformly
// kCappedImageValue). Throws std::invalid_argument for an index out of range.
Image RenderRigFrame(const RenderedRig& rig, size_t camera, size_t index);

// ground_truth.json: the single-camera file (GroundTruthJson) of the
// reference camera, its images named as in the rig, plus "rig" (name,
// reference camera, image layout) and "cameras", per camera: name,
// camera_id (cameras.txt), image_prefix, reference, capped, odom_from_cam
// and cam_from_odom (as the top-level ones), camera (COLMAP intrinsics),
// rate_hz, phase_s, camera_time_offset_s, num_images and images (as the
// top-level ones). Pretty-printed.
std::string RigGroundTruthJson(const RenderedRig& rig);

// cameras.txt: COLMAP's text format, one line per camera (camera_id = its
// position in the rig, from 1), each after a comment naming the camera, its
// folder and the same intrinsics as `odomcal run` flags (--camera_model,
// --camera_params).
std::string RigCamerasText(const RenderedRig& rig);

// Writes into `output_dir` (created if missing; existing files replaced):
//   images/<name>/<stamp>.png  8-bit RGB PNG per frame, per camera
//   image_timestamps.csv       image_name,timestamp for every camera's
//                              images, "<name>/<stamp>.png" (recorded, s,
//                              9 decimals), camera by camera
//   cameras.txt                RigCamerasText
//   ground_truth.json          RigGroundTruthJson
//   odometry.csv, odometry_ground_truth.csv (and odometry_se3.tum for
//   roads) as WriteRenderedDataset writes them.
// `progress(done, total)` is called after each image. Throws
// std::runtime_error naming the path on I/O errors.
void WriteRenderedRig(
    const RenderedRig& rig,
    const std::string& output_dir,
    const std::function<void(size_t done, size_t total)>& progress = {});

}  // namespace odomcal
