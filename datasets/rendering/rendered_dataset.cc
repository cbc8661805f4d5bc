// SimulateRenderedDataset: derive the seeds, plan the path long enough for
// the timeline, simulate the odometry at its own rate, and place each image
// at its capture time; WriteRenderedDataset then renders frame by frame and
// writes the files (images with OpenCV, logs with the adapters' writers).

#include "odomcal/datasets/rendering/rendered_dataset.h"

#include "odomcal/adapters/timestamp.h"
#include "odomcal/datasets/rendering/rendered_files_internal.h"
#include "odomcal/datasets/simulation/seed.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <stdexcept>

namespace odomcal {

using internal::FrameJson;
using internal::IntrinsicsJson;
using internal::TransformJson;

void RenderedDatasetOptions::Check() const {
  camera.Check();
  layout.Check();
  scene.Check();
  render.Check();
  odometry_noise.Check();
  if (road) road->Check();
  if (num_images < 2) {
    throw std::invalid_argument(
        "RenderedDatasetOptions.num_images must be >= 2");
  }
  if (!(camera_rate_hz > 0.0) || !(odometry_rate_hz >= camera_rate_hz)) {
    throw std::invalid_argument(
        "RenderedDatasetOptions: need 0 < camera_rate_hz <= odometry_rate_hz");
  }
  if (!(lead_time_s >= 0.0) || !std::isfinite(camera_time_offset_s)) {
    throw std::invalid_argument(
        "RenderedDatasetOptions: lead_time_s >= 0, finite "
        "camera_time_offset_s");
  }
  // Recorded stamps must stay in order: jitter well below the period.
  if (!(camera_time_jitter_s >= 0.0) ||
      camera_time_jitter_s * camera_rate_hz > 0.05) {
    throw std::invalid_argument(
        "RenderedDatasetOptions.camera_time_jitter_s must be in [0, 0.05 / "
        "camera_rate_hz]");
  }
}

RenderedDataset SimulateDatasetMotion(const RenderedDatasetOptions& options) {
  options.Check();
  RenderedDataset dataset;
  RenderedDatasetOptions& o = dataset.options;
  o = options;
  o.scene.seed = DeriveSeed(o.seed, 1);
  o.path.seed = DeriveSeed(o.seed, 2);
  o.odometry_noise.seed = DeriveSeed(o.seed, 3);
  o.path.camera_position_in_odom = o.odom_from_cam.translation;
  o.path.camera_axis_in_odom =
      o.odom_from_cam.rotation * Eigen::Vector3d::UnitZ();

  if (o.road) {
    // The scene reaches 30 m beyond the end of the drive.
    const std::vector<RoutePiece> route = RoadRoute(*o.road);
    double before_last = 0.0;
    for (size_t i = 0; i + 1 < route.size(); ++i) {
      before_last += route[i].length_m;
    }
    const double drive_m =
        o.road->speed_mps *
        (2.0 * o.lead_time_s + (o.num_images - 1) / o.camera_rate_hz);
    o.road->last_straight_m =
        std::max(o.road->last_straight_m, drive_m - before_last + 30.0);
  }

  // Timeline in ns from the first odometry sample.
  std::vector<int64_t> captures;
  captures.reserve(o.num_images);
  for (int k = 0; k < o.num_images; ++k) {
    captures.push_back(SecondsToNs(o.lead_time_s + k / o.camera_rate_hz));
  }
  const int64_t odometry_end = captures.back() + SecondsToNs(o.lead_time_s);
  o.path.duration_s = 1e-9 * odometry_end;

  std::vector<int64_t> samples;
  const double period_s = 1.0 / o.odometry_rate_hz;
  for (int64_t k = 0;; ++k) {
    samples.push_back(SecondsToNs(k * period_s));
    if (samples.back() >= odometry_end) break;
  }
  // room_from_odom at path time t.
  std::function<Rigid3d(int64_t)> body_pose;
  if (o.road) {
    dataset.path = MakeRoadPath(*o.road, o.path.duration_s);
    dataset.road_ground = MakeRoadGround(*o.road);
    const UnicyclePath& path = dataset.path;
    const RoadGround& ground = *dataset.road_ground;
    body_pose = [&ground, &path](int64_t t) {
      return PoseOnGround(ground, path.PoseAt(t));
    };
    // The wheels' true steps: distance along the ground and turn about the
    // car's up axis, summed over 8 sub-steps per period.
    std::vector<Eigen::Vector2d> steps;
    for (size_t k = 1; k < samples.size(); ++k) {
      Eigen::Vector2d step = Eigen::Vector2d::Zero();
      Rigid3d previous = body_pose(samples[k - 1]);
      for (int j = 1; j <= 8; ++j) {
        const Rigid3d next =
            body_pose(samples[k - 1] + (samples[k] - samples[k - 1]) * j / 8);
        const Eigen::Matrix3d relative =
            (previous.rotation.conjugate() * next.rotation).toRotationMatrix();
        step.x() += (next.translation - previous.translation).norm();
        step.y() += std::atan2(relative(1, 0), relative(0, 0));
        previous = next;
      }
      steps.push_back(step);
    }
    dataset.odometry = SimulateWheelOdometryFromSteps(
        steps, samples, o.start_stamp_ns, o.odometry_noise);
    dataset.true_odometry = SimulateWheelOdometryFromSteps(
        steps, samples, o.start_stamp_ns, WheelOdometryNoise());
    dataset.true_odometry.source = "true wheel odometry";
  } else {
    dataset.path = PlanRoomPath(o.layout, o.path);
    dataset.odometry = SimulateWheelOdometry(
        dataset.path, samples, o.start_stamp_ns, o.odometry_noise);
    dataset.true_odometry =
        TrueWheelOdometry(dataset.path, samples, o.start_stamp_ns);
    const UnicyclePath& path = dataset.path;
    body_pose = [&path](int64_t t) { return path.PoseAt(t).ToRigid3d(); };
  }
  dataset.room_from_origin = body_pose(0);
  const Rigid3d origin_from_room = Inverse(dataset.room_from_origin);
  if (o.road) {
    dataset.true_odometry_se3.source = "true SE(3) odometry";
    for (const int64_t t : samples) {
      dataset.true_odometry_se3.poses.push_back(
          {t + o.start_stamp_ns, origin_from_room * body_pose(t)});
    }
  }

  std::mt19937_64 jitter_rng(DeriveSeed(o.seed, 4));
  std::normal_distribution<double> jitter(0.0, o.camera_time_jitter_s);
  for (int k = 0; k < o.num_images; ++k) {
    RenderedFrame frame;
    char name[32];
    std::snprintf(name, sizeof(name), "%06d.png", k);
    frame.image_name = name;
    frame.capture_ns = o.start_stamp_ns + captures[k];
    const double noise_s =
        o.camera_time_jitter_s > 0.0 ? jitter(jitter_rng) : 0.0;
    frame.stamp_ns =
        frame.capture_ns + SecondsToNs(o.camera_time_offset_s + noise_s);
    frame.room_from_cam = body_pose(captures[k]) * o.odom_from_cam;
    frame.origin_from_cam = origin_from_room * frame.room_from_cam;
    dataset.frames.push_back(frame);
  }
  return dataset;
}

Rigid3d RoomFromOdomAt(const RenderedDataset& dataset, int64_t path_time_ns) {
  const PlanarPose pose = dataset.path.PoseAt(path_time_ns);
  return dataset.road_ground ? PoseOnGround(*dataset.road_ground, pose)
                             : pose.ToRigid3d();
}

RenderedDataset SimulateRenderedDataset(const RenderedDatasetOptions& options) {
  RenderedDataset dataset = SimulateDatasetMotion(options);
  const RenderedDatasetOptions& o = dataset.options;
  dataset.scene = o.road ? BuildRoadScene(*o.road, o.scene)
                         : BuildRoomScene(o.layout, o.scene);
  return dataset;
}

Image RenderFrame(const RenderedDataset& dataset, size_t index) {
  if (index >= dataset.frames.size()) {
    throw std::invalid_argument("RenderFrame: index out of range");
  }
  return RenderImage(dataset.scene,
                     dataset.options.camera,
                     dataset.frames[index].room_from_cam,
                     dataset.options.render);
}

std::string GroundTruthJson(const RenderedDataset& dataset) {
  const RenderedDatasetOptions& o = dataset.options;
  nlohmann::json images = nlohmann::json::array();
  for (const RenderedFrame& frame : dataset.frames) {
    images.push_back(FrameJson(frame));
  }
  const WheelOdometryNoise& n = o.odometry_noise;
  nlohmann::json truth = {
      {"schema", "odomcal.rendered_dataset"},
      {"schema_version", 1},
      {"preset", o.preset},
      {"seed", o.seed},
      {"conventions",
       {{"transforms",
         "b_from_a maps coordinates in a to b: x_in_b = b_from_a * x_in_a"},
        {"quaternion", "Hamilton, order w x y z"},
        {"frames",
         "cam: x right, y down, z forward; odom: robot body, x forward, y "
         "left, "
         "z up, on the floor; world: the odometry's origin (robot pose at the "
         "first odometry sample); metres"},
        {"timestamps",
         "seconds, exact 9-decimal text; timestamp = capture_timestamp + "
         "camera_time_offset_s + jitter"},
        {"pixels",
         "COLMAP: pixel (i, j) covers [i, i+1) x [j, j+1), centre at +0.5"}}},
      {"odom_from_cam", TransformJson(o.odom_from_cam)},
      {"cam_from_odom", TransformJson(Inverse(o.odom_from_cam))},
      {"metric_scale", 1.0},
      {"camera", IntrinsicsJson(o.camera)},
      {"timing",
       {{"camera_rate_hz", o.camera_rate_hz},
        {"odometry_rate_hz", o.odometry_rate_hz},
        {"camera_time_offset_s", o.camera_time_offset_s},
        {"camera_time_jitter_s", o.camera_time_jitter_s},
        {"note",
         "the camera clock runs late by camera_time_offset_s: odomcal "
         "calibrate --camera_time_offset_s should be its negative"}}},
      {"odometry_noise",
       {{"wheel_base_m", n.wheel_base_m},
        {"wheel_scale_error_left", n.wheel_scale_error_left},
        {"wheel_scale_error_right", n.wheel_scale_error_right},
        {"wheel_slip_stddev", n.wheel_slip_stddev},
        {"yaw_rate_bias_radps", n.yaw_rate_bias_radps}}},
      {"scene",
       {{"room_from_world", TransformJson(dataset.room_from_origin)},
        {"num_surfaces", dataset.scene.surfaces.size()},
        {"floor_slope_deg", o.layout.floor_slope_deg},
        {"floor_textured",
         std::all_of(o.layout.floors.begin(),
                     o.layout.floors.end(),
                     [](const FloorPatch& floor) { return floor.textured; })},
        {"texel_size_m", o.scene.texel_size_m},
        {"supersampling", o.render.supersampling}}},
      {"images", images},
  };
  if (o.road) {
    const RoadOptions& r = *o.road;
    truth["scene"]["road"] = {
        {"speed_mps", r.speed_mps},
        {"first_straight_m", r.first_straight_m},
        {"turn_radius_m", r.turn_radius_m},
        {"left_turn_deg", r.left_turn_deg},
        {"middle_straight_m", r.middle_straight_m},
        {"right_turn_deg", r.right_turn_deg},
        {"last_straight_m", r.last_straight_m},
        {"road_width_m", r.road_width_m},
        {"lane_offset_m", r.lane_offset_m},
        {"ground_cell_m", r.ground_cell_m},
        {"slope_x_deg", r.slope_x_deg},
        {"slope_y_deg", r.slope_y_deg},
        {"slope_wavelength_m", r.slope_wavelength_m},
        {"road_patch_fraction", r.road_patch_fraction},
        {"note",
         "the car rides on the ground: world_from_cam and odometry_se3.tum "
         "are SE(3); odometry.csv integrates the distance along the ground "
         "and the turn about the car's up axis as if flat"}};
  }
  return truth.dump(2) + "\n";
}

void WriteRenderedDataset(
    const RenderedDataset& dataset,
    const std::string& output_dir,
    const std::function<void(size_t done, size_t total)>& progress) {
  namespace fs = std::filesystem;
  const fs::path root(output_dir);
  const fs::path images = root / "images";
  std::error_code error;
  fs::create_directories(images, error);
  if (error || !fs::is_directory(images)) {
    throw std::runtime_error(images.string() + ": cannot create the folder");
  }
  std::string timestamps = "image_name,timestamp\n";
  for (size_t i = 0; i < dataset.frames.size(); ++i) {
    internal::WritePng(RenderFrame(dataset, i),
                       (images / dataset.frames[i].image_name).string());
    timestamps += dataset.frames[i].image_name + "," +
                  FormatTimestampSeconds(dataset.frames[i].stamp_ns) + "\n";
    if (progress) progress(i + 1, dataset.frames.size());
  }
  internal::WriteOdometryFiles(dataset, output_dir);
  internal::WriteTextFile((root / "image_timestamps.csv").string(), timestamps);
  internal::WriteTextFile((root / "ground_truth.json").string(),
                          GroundTruthJson(dataset));
}

}  // namespace odomcal
