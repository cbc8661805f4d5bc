#include "odomcal/plugin/colmap/floor_height.h"

#include "odomcal/solver/floor_translation_z.h"
#include "odomcal/solver/format_number.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <utility>

namespace odomcal {
namespace {

constexpr double kMinReprojectionErrorPx = 0.5;
// Rays closer to parallel than this give no depth: the sigma is capped.
constexpr double kMinSineParallax = 0.02;

double FocalLengthPx(const ColmapCamera& camera) {
  const auto indices = ColmapCameraModelPinholeIndices(camera.model);
  if (!indices || camera.params.size() <=
                      static_cast<size_t>(std::max(indices->fx, indices->fy))) {
    return std::max<double>(camera.width, camera.height);
  }
  return 0.5 * (camera.params[indices->fx] + camera.params[indices->fy]);
}

// Among the models' cameras of two focal lengths, the fx / fy furthest from
// its value before the bundle adjustment, over that value: the database's
// camera of the same id, else the one value every database camera has, else
// square pixels (1). 1 where no camera has two focal lengths.
double PixelAspectChange(
    const std::vector<MetricSubModel>& models,
    const std::map<uint32_t, ColmapCamera>& database_cameras) {
  std::map<uint32_t, double> database_aspects;
  for (const auto& [id, camera] : database_cameras) {
    if (const std::optional<double> aspect = PixelAspectOf(camera)) {
      database_aspects[id] = *aspect;
    }
  }
  // The one value of every database camera, else square pixels.
  double common =
      database_aspects.empty() ? 1.0 : database_aspects.begin()->second;
  for (const auto& [id, aspect] : database_aspects) {
    if (aspect != common) common = 1.0;
  }
  double furthest = 1.0;
  for (const MetricSubModel& metric : models) {
    for (const auto& [id, camera] : metric.model.cameras) {
      const std::optional<double> aspect = PixelAspectOf(camera);
      if (!aspect) continue;
      const auto given = database_aspects.find(id);
      // The joint adjustment's model numbers its cameras anew: only the
      // common value is theirs for sure.
      const double before =
          metric.origin_from_sfm && given != database_aspects.end()
              ? given->second
              : common;
      const double change = *aspect / before;
      if (std::abs(change - 1.0) > std::abs(furthest - 1.0)) furthest = change;
    }
  }
  return furthest;
}

}  // namespace

std::optional<double> PixelAspectOf(const ColmapCamera& camera) {
  const auto indices = ColmapCameraModelPinholeIndices(camera.model);
  if (!indices || indices->fx == indices->fy ||
      camera.params.size() <=
          static_cast<size_t>(std::max(indices->fx, indices->fy))) {
    return std::nullopt;
  }
  const double aspect = camera.params[indices->fx] / camera.params[indices->fy];
  if (!std::isfinite(aspect) || !(aspect > 0.0)) return std::nullopt;
  return aspect;
}

FloorInput FloorInputOf(const std::vector<MetricSubModel>& models,
                        const std::map<std::string, int64_t>& stamp_of_image) {
  // Cameras: (has no stamp, stamp, name) sorts in time, then by name.
  struct Entry {
    bool no_stamp;
    int64_t stamp;
    std::string name;
    size_t model;
    uint32_t image_id;
  };
  std::vector<Entry> ordered;
  for (size_t k = 0; k < models.size(); ++k) {
    for (const auto& [id, image] : models[k].model.images) {
      const auto stamp = stamp_of_image.find(image.name);
      ordered.push_back({stamp == stamp_of_image.end(),
                         stamp == stamp_of_image.end() ? 0 : stamp->second,
                         image.name,
                         k,
                         id});
    }
  }
  std::sort(ordered.begin(), ordered.end(), [](const Entry& a, const Entry& b) {
    return std::tie(a.no_stamp, a.stamp, a.name) <
           std::tie(b.no_stamp, b.stamp, b.name);
  });
  FloorInput input;
  std::map<std::pair<size_t, uint32_t>, int> index_of;
  for (const Entry& entry : ordered) {
    const MetricSubModel& metric = models[entry.model];
    index_of[{entry.model, entry.image_id}] =
        static_cast<int>(input.cameras.size());
    input.cameras.push_back(
        {Inverse(metric.model.images.at(entry.image_id).cam_from_world),
         metric.output_segment});
  }
  for (size_t k = 0; k < models.size(); ++k) {
    const ColmapModel& model = models[k].model;
    for (const auto& [id, point] : model.points3D) {
      double nearest = std::numeric_limits<double>::infinity();
      double focal = 0.0;
      int camera = -1;
      std::vector<Eigen::Vector3d> rays;
      for (const ColmapTrackElement& element : point.track) {
        const auto image = model.images.find(element.image_id);
        if (image == model.images.end()) continue;
        const Rigid3d origin_from_cam = Inverse(image->second.cam_from_world);
        const Eigen::Vector3d ray = point.xyz - origin_from_cam.translation;
        const double distance = ray.norm();
        if (!(distance > 0.0)) continue;
        rays.push_back(ray / distance);
        if (distance < nearest) {
          nearest = distance;
          camera = index_of.at({k, element.image_id});
          const auto intrinsics = model.cameras.find(image->second.camera_id);
          focal = intrinsics == model.cameras.end()
                      ? 0.0
                      : FocalLengthPx(intrinsics->second);
        }
      }
      if (rays.size() < 2 || !(focal > 0.0)) continue;
      double max_sine = 0.0;
      for (size_t i = 0; i < rays.size(); ++i) {
        for (size_t j = i + 1; j < rays.size(); ++j) {
          max_sine = std::max(max_sine, rays[i].cross(rays[j]).norm());
        }
      }
      const double angle =
          std::max(point.error, kMinReprojectionErrorPx) / focal;
      const double lateral = angle * nearest;
      const double depth = lateral / std::max(max_sine, kMinSineParallax);
      input.points.push_back(
          {point.xyz, std::hypot(lateral, depth), camera, nearest});
    }
  }
  return input;
}

void ApplyFloorPlane(const FloorPlaneOptions& options,
                     double max_translation_stddev_m,
                     const std::map<std::string, int64_t>& stamp_of_image,
                     const MetricSubModel* agreeing_joint_model,
                     ColmapCalibrationRun* run) {
  CalibrationResult& result = run->check.result;
  if (options.use == FloorPlaneUse::kOff || run->metric_models.empty() ||
      !result.has_estimate) {
    return;
  }
  const FloorInput input = FloorInputOf(run->metric_models, stamp_of_image);
  FloorPlane floor = FitFloorPlane(input.points,
                                   input.cameras,
                                   result.odom_from_cam,
                                   RollPitchCovariance(result),
                                   result.metric_scales,
                                   options);
  if (floor.Fitted() && agreeing_joint_model) {
    const JointAdjustmentResult& joint = run->joint.result;
    const FloorInput joint_input =
        FloorInputOf({*agreeing_joint_model}, stamp_of_image);
    const FloorPlane joint_floor =
        FitFloorPlane(joint_input.points,
                      joint_input.cameras,
                      joint.odom_from_cam,
                      joint.covariance.topLeftCorner<2, 2>(),
                      result.metric_scales,
                      options);
    if (joint_floor.Fitted()) {
      floor.camera_height_model_difference_m =
          joint_floor.camera_height_m - floor.camera_height_m;
      floor.camera_height_stddev_m = std::hypot(
          floor.camera_height_stddev_m, floor.camera_height_model_difference_m);
    }
  }
  floor.pixel_aspect_change =
      PixelAspectChange(run->metric_models, run->database_cameras);
  if (floor.Fitted() && floor.pixel_aspect_change != 1.0) {
    floor.camera_height_pixel_aspect_m =
        std::abs(floor.pixel_aspect_change - 1.0) * floor.camera_height_m;
    const double own = floor.camera_height_stddev_m;
    floor.camera_height_stddev_m =
        std::hypot(own, floor.camera_height_pixel_aspect_m);
    if (floor.camera_height_pixel_aspect_m > own) {
      result.warnings.push_back(
          "floor plane: the model's camera has fx / fy " +
          FormatPrintf("%.4f", floor.pixel_aspect_change) +
          " times its value before the bundle adjustment (or square pixels), "
          "and motion in a plane does not fix the focal length along its "
          "normal apart from the one across it: the camera height from the "
          "floor is uncertain by " +
          FormatPrintf("%.1f mm", 1000.0 * floor.camera_height_pixel_aspect_m) +
          " more than its own " + FormatPrintf("%.1f mm", 1000.0 * own) +
          ". Give the camera's intrinsics and keep them fixed in the bundle "
          "adjustment (COLMAP: --Mapper.ba_refine_focal_length 0), or map "
          "with a camera model of one focal length");
    }
  }
  const double held_z = result.odom_from_cam.translation.z();
  result.floor_z_held_reason = SetTranslationZFromFloor(
      floor, options, max_translation_stddev_m, &result);
  result.floor_plane = floor;
  if (floor.status == FloorPlaneStatus::kSloped ||
      floor.status == FloorPlaneStatus::kDisagreesWithMotion ||
      floor.status == FloorPlaneStatus::kTiltUncertain) {
    result.warnings.push_back("floor plane: " + floor.reason +
                              "; translation z stays held");
  }
  const double dz = result.odom_from_cam.translation.z() - held_z;
  if (dz == 0.0) return;
  // Every camera moves by dz along the odometry's z, and so does the model.
  for (MetricSubModel& metric : run->metric_models) {
    if (metric.origin_from_sfm) metric.origin_from_sfm->translation.z() += dz;
    for (auto& [id, image] : metric.model.images) {
      image.cam_from_world.translation -=
          image.cam_from_world.rotation * Eigen::Vector3d(0.0, 0.0, dz);
    }
    for (auto& [id, point] : metric.model.points3D) point.xyz.z() += dz;
  }
}

}  // namespace odomcal
