#include "odomcal/adapters/colmap_model_subset.h"

namespace odomcal {

ColmapModel ColmapModelSubset(const ColmapModel& model,
                              const std::set<uint32_t>& image_ids,
                              int min_track_length) {
  ColmapModel subset;
  for (const auto& [id, image] : model.images) {
    if (image_ids.count(id) == 0) continue;
    subset.images.emplace(id, image);
    const auto camera = model.cameras.find(image.camera_id);
    if (camera != model.cameras.end()) subset.cameras.insert(*camera);
  }
  for (const auto& [id, point] : model.points3D) {
    ColmapPoint3D kept = point;
    kept.track.clear();
    for (const ColmapTrackElement& element : point.track) {
      if (subset.images.count(element.image_id) != 0)
        kept.track.push_back(element);
    }
    if (static_cast<int>(kept.track.size()) >= min_track_length) {
      subset.points3D.emplace(id, std::move(kept));
    }
  }
  for (auto& [id, image] : subset.images) {
    for (ColmapPoint2D& point : image.points2D) {
      if (point.point3D_id != kColmapNoPoint3D &&
          subset.points3D.count(point.point3D_id) == 0) {
        point.point3D_id = kColmapNoPoint3D;
      }
    }
  }
  return subset;
}

}  // namespace odomcal
