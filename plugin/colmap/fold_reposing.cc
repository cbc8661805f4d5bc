#include "odomcal/plugin/colmap/fold_reposing.h"

#include "odomcal/adapters/association.h"

#include <cmath>
#include <cstdlib>
#include <set>
#include <stdexcept>

namespace odomcal {

std::optional<ReposedModel> ReposeFoldFromOdometry(const ColmapModel& model,
                                                   const ColmapSegment& segment,
                                                   const Trajectory& odometry,
                                                   const FoldToRepose& fold) {
  if (!(fold.metres_per_unit > 0.0) || !std::isfinite(fold.metres_per_unit)) {
    throw std::invalid_argument(
        "ReposeFoldFromOdometry: metres_per_unit must be positive and finite");
  }
  constexpr int64_t kStampToleranceNs = 1'000'000;
  const std::vector<StampedPose>& poses = segment.trajectory.poses;
  size_t anchor = poses.size();
  for (size_t i = 0; i < poses.size(); ++i) {
    if (std::llabs(poses[i].stamp_ns + fold.camera_time_offset_ns -
                   fold.first_stamp_ns) <= kStampToleranceNs) {
      anchor = i;
      break;
    }
  }
  if (anchor == poses.size()) return std::nullopt;
  auto odometry_at = [&](size_t i) {
    return InterpolateOdometry(odometry,
                               poses[i].stamp_ns + fold.camera_time_offset_ns,
                               fold.max_odometry_gap_s,
                               nullptr);
  };
  const std::optional<Rigid3d> origin_from_anchor_odom = odometry_at(anchor);
  if (!origin_from_anchor_odom) return std::nullopt;
  const auto anchor_image = model.images.find(segment.image_ids[anchor]);
  if (anchor_image == model.images.end()) return std::nullopt;
  const Rigid3d world_from_anchor_cam =
      Inverse(anchor_image->second.cam_from_world);
  const Rigid3d cam_from_odom = Inverse(fold.odom_from_cam);

  ReposedModel reposed;
  reposed.model = model;
  reposed.anchor_image = anchor_image->second.name;
  // Images the segment does not hold (no timestamp) cannot be placed.
  std::set<uint32_t> keep(segment.image_ids.begin(),
                          segment.image_ids.begin() + anchor + 1);
  for (size_t i = anchor + 1; i < poses.size(); ++i) {
    const auto image = reposed.model.images.find(segment.image_ids[i]);
    const std::optional<Rigid3d> origin_from_odom = odometry_at(i);
    if (image == reposed.model.images.end() || !origin_from_odom) {
      ++reposed.num_left_out;
      continue;
    }
    // Metres in the anchor camera's frame, then the sub-model's units.
    Rigid3d anchor_cam_from_cam = cam_from_odom *
                                  Inverse(*origin_from_anchor_odom) *
                                  *origin_from_odom * fold.odom_from_cam;
    anchor_cam_from_cam.translation /= fold.metres_per_unit;
    image->second.cam_from_world =
        Inverse(world_from_anchor_cam * anchor_cam_from_cam);
    keep.insert(image->first);
    reposed.reposed_image_ids.push_back(image->first);
    ++reposed.num_reposed;
  }
  if (reposed.num_reposed == 0) return std::nullopt;
  for (auto it = reposed.model.images.begin();
       it != reposed.model.images.end();) {
    it = keep.count(it->first) == 0 ? reposed.model.images.erase(it)
                                    : std::next(it);
  }
  reposed.model.points3D.clear();
  for (auto& [id, image] : reposed.model.images) {
    for (ColmapPoint2D& point : image.points2D) {
      point.point3D_id = kColmapNoPoint3D;
    }
  }
  return reposed;
}

}  // namespace odomcal
