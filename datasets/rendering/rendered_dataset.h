// A rendered calibration dataset: a camera rigidly mounted on a
// differential-drive robot that drives through a textured room, with wheel
// odometry, image timestamps and the ground truth.
//
// Timeline (ns): path time 0 is the first odometry sample; odometry is
// sampled every 1 / odometry_rate_hz until lead_time_s after the last image.
// Image k is captured at path time lead_time_s + k / camera_rate_hz and
// rendered at the robot's true pose then; its *recorded* timestamp is
//   stamp = capture + camera_time_offset_s + jitter_k,  jitter ~ N(0, sigma),
// i.e. a camera clock that runs late by the offset. Absolute stamps add
// start_stamp_ns. Frames: `room` (the scene), `origin` (the odometry's fixed
// frame = the robot's pose at path time 0), `odom` (the body), `cam`.
// True camera poses are origin_from_cam = origin_from_odom_true(capture) *
// odom_from_cam, in metres: the scene is metric, so is the reconstruction's
// true scale.
//
// Deterministic for the options: the scene, the path, the odometry noise and
// the time jitter each use their own stream derived from `seed` (seed.h).
//
// With `road` set the scene is a road (road_scene.h) instead of the room:
// layout and path are unused, the car drives the road's route and rides on
// its ground (SE(3) poses: room_from_origin and the true camera poses pitch
// and bank with it), and the wheel odometry integrates, as if flat, the
// distance driven along the ground and the turn about the car's up axis
// (SimulateWheelOdometryFromSteps): planar odometry of a drive that is not.
#pragma once

#include "odomcal/adapters/trajectory.h"
#include "odomcal/datasets/rendering/camera_model.h"
#include "odomcal/datasets/rendering/ray_caster.h"
#include "odomcal/datasets/rendering/road_scene.h"
#include "odomcal/datasets/rendering/room_layout.h"
#include "odomcal/datasets/rendering/room_path.h"
#include "odomcal/datasets/rendering/room_scene.h"
#include "odomcal/datasets/simulation/wheel_odometry.h"
#include "odomcal/solver/rigid3.h"

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace odomcal {

struct RenderedDatasetOptions {
  std::string preset = "custom";  // echoed in ground_truth.json
  uint64_t seed = 0;
  CameraIntrinsics camera;
  Rigid3d odom_from_cam;
  RoomLayout layout;
  // scene.seed, path.seed, path.duration_s and path.camera_* are derived
  // (from seed, the timeline and odom_from_cam) and overwritten.
  RoomSceneOptions scene;
  RoomPathOptions path;
  // A road instead of the room; its last_straight_m is lengthened to reach
  // 30 m beyond where the drive ends.
  std::optional<RoadOptions> road;
  int num_images = 40;
  double camera_rate_hz = 4.0;
  double odometry_rate_hz = 50.0;
  double lead_time_s = 0.5;
  double camera_time_offset_s = 0.0;
  double camera_time_jitter_s = 0.0;  // standard deviation
  WheelOdometryNoise odometry_noise;  // its seed is derived too
  RenderOptions render;
  int64_t start_stamp_ns = 1700000000000000000;
  void Check() const;  // throws std::invalid_argument naming the field
};

struct RenderedFrame {
  std::string image_name;   // "000000.png": sorts in time order
  int64_t capture_ns = 0;   // true capture time on the odometry clock
  int64_t stamp_ns = 0;     // recorded timestamp
  Rigid3d origin_from_cam;  // true pose
  Rigid3d room_from_cam;
};

struct RenderedDataset {
  RenderedDatasetOptions options;  // with the derived seeds filled in
  RoomScene scene;
  UnicyclePath path;
  Rigid3d room_from_origin;
  Trajectory odometry;       // measured, origin_from_odom
  Trajectory true_odometry;  // exact, same stamps (road: noise-free wheels)
  // Road scenes: origin_from_odom in SE(3), the car's true poses, same stamps
  // (empty for rooms, whose odometry is exact in the plane).
  Trajectory true_odometry_se3;
  // Road scenes: the ground the car rides on.
  std::optional<RoadGround> road_ground;
  std::vector<RenderedFrame> frames;
};

// Plans the path and simulates odometry and timestamps: everything except the
// scene (dataset.scene stays empty) and the pixels. Throws
// std::invalid_argument for bad options, std::runtime_error when the path
// cannot be planned.
RenderedDataset SimulateDatasetMotion(const RenderedDatasetOptions& options);

// The robot's true pose room_from_odom at path time `path_time_ns` (ns from
// the first odometry sample), as the frames' poses use it: on the path, and
// for roads on the ground.
Rigid3d RoomFromOdomAt(const RenderedDataset& dataset, int64_t path_time_ns);

// SimulateDatasetMotion plus the textured scene: ready to render.
RenderedDataset SimulateRenderedDataset(const RenderedDatasetOptions& options);

// The image of frame `index` (0 <= index < frames.size()).
Image RenderFrame(const RenderedDataset& dataset, size_t index);

// ground_truth.json (see WriteRenderedDataset), pretty-printed.
std::string GroundTruthJson(const RenderedDataset& dataset);

// Writes into `output_dir` (created if missing; existing files replaced):
//   images/NNNNNN.png          8-bit RGB PNG per frame
//   odometry.csv               measured odometry, timestamp,x,y,yaw
//   odometry_ground_truth.csv  the true odometry at the same stamps (road:
//                              the noise-free planar wheel odometry)
//   odometry_se3.tum           road scenes only: the true SE(3) odometry
//                              (TUM: timestamp tx ty tz qx qy qz qw)
//   image_timestamps.csv       image_name,timestamp (recorded, s, 9 decimals)
//   ground_truth.json          odom_from_cam (quaternion_wxyz, translation_m,
//                              4x4 matrix) and its inverse, intrinsics
//                              (COLMAP model, size, params), per image the
//                              recorded and capture times and the true
//                              world_from_cam (world = origin), the preset,
//                              seed, timing and noise parameters.
// `progress(done, total)` is called after each image. Throws
// std::runtime_error naming the path on I/O errors.
void WriteRenderedDataset(
    const RenderedDataset& dataset,
    const std::string& output_dir,
    const std::function<void(size_t done, size_t total)>& progress = {});

}  // namespace odomcal
