#include "odomcal/plugin/colmap/floor_height.h"

#include "odomcal/solver/floor_translation_z.h"

#include <algorithm>
#include <cmath>
#include <tuple>

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

}  // namespace

std::vector<FloorCandidatePoint> FloorCandidatesOf(
    const std::vector<MetricSubModel>& models) {
  std::vector<FloorCandidatePoint> points;
  for (const MetricSubModel& metric : models) {
    const ColmapModel& model = metric.model;
    for (const auto& [id, point] : model.points3D) {
      double nearest = std::numeric_limits<double>::infinity();
      double focal = 0.0;
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
          const auto camera = model.cameras.find(image->second.camera_id);
          focal = camera == model.cameras.end() ? 0.0
                                                : FocalLengthPx(camera->second);
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
      points.push_back({point.xyz, std::hypot(lateral, depth)});
    }
  }
  return points;
}

std::vector<FloorCamera> FloorCamerasOf(
    const std::vector<MetricSubModel>& models,
    const std::map<std::string, int64_t>& stamp_of_image) {
  // (has no stamp, stamp, name) sorts in time, then by name.
  std::vector<std::tuple<bool, int64_t, std::string, FloorCamera>> ordered;
  for (const MetricSubModel& metric : models) {
    for (const auto& [id, image] : metric.model.images) {
      const auto stamp = stamp_of_image.find(image.name);
      ordered.emplace_back(
          stamp == stamp_of_image.end(),
          stamp == stamp_of_image.end() ? 0 : stamp->second,
          image.name,
          FloorCamera{Inverse(image.cam_from_world), metric.output_segment});
    }
  }
  std::sort(ordered.begin(), ordered.end(), [](const auto& a, const auto& b) {
    return std::tie(std::get<0>(a), std::get<1>(a), std::get<2>(a)) <
           std::tie(std::get<0>(b), std::get<1>(b), std::get<2>(b));
  });
  std::vector<FloorCamera> cameras;
  cameras.reserve(ordered.size());
  for (auto& entry : ordered) cameras.push_back(std::get<3>(entry));
  return cameras;
}

void ApplyFloorPlane(const FloorPlaneOptions& options,
                     double max_translation_stddev_m,
                     const std::map<std::string, int64_t>& stamp_of_image,
                     ColmapCalibrationRun* run) {
  CalibrationResult& result = run->check.result;
  if (options.use == FloorPlaneUse::kOff || run->metric_models.empty() ||
      !result.has_estimate) {
    return;
  }
  const FloorPlane floor =
      FitFloorPlane(FloorCandidatesOf(run->metric_models),
                    FloorCamerasOf(run->metric_models, stamp_of_image),
                    result.odom_from_cam,
                    RollPitchCovariance(result),
                    result.metric_scales,
                    options);
  const double held_z = result.odom_from_cam.translation.z();
  result.floor_z_held_reason = SetTranslationZFromFloor(
      floor, options, max_translation_stddev_m, &result);
  result.floor_plane = floor;
  if (floor.status == FloorPlaneStatus::kSloped ||
      floor.status == FloorPlaneStatus::kDisagreesWithMotion) {
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
