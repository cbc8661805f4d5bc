#include "odomcal/adapters/colmap_model_subset.h"

#include <gtest/gtest.h>

namespace odomcal {
namespace {

// Three images on two cameras; point 10 seen by images 1, 2, 3, point 11 by
// images 2 and 3, point 12 by images 1 and 2.
ColmapModel ThreeImageModel() {
  ColmapModel model;
  model.cameras[1] = {
      1, ColmapCameraModel::kPinhole, 320, 240, {260, 260, 160, 120}};
  model.cameras[2] = {
      2, ColmapCameraModel::kPinhole, 320, 240, {250, 250, 160, 120}};
  for (uint32_t id = 1; id <= 3; ++id) {
    ColmapImage image;
    image.image_id = id;
    image.name = std::to_string(id) + ".png";
    image.camera_id = id == 3 ? 2 : 1;
    image.points2D.resize(3);
    model.images[id] = image;
  }
  const auto link = [&](int64_t point_id, uint32_t image_id, uint32_t index) {
    model.points3D[point_id].point3D_id = point_id;
    model.points3D[point_id].track.push_back({image_id, index});
    model.images[image_id].points2D[index].point3D_id = point_id;
  };
  link(10, 1, 0);
  link(10, 2, 0);
  link(10, 3, 0);
  link(11, 2, 1);
  link(11, 3, 1);
  link(12, 1, 2);
  link(12, 2, 2);
  return model;
}

TEST(ColmapModelSubset, KeepsImagesTheirCamerasAndPointsTheyStillTriangulate) {
  const ColmapModel subset = ColmapModelSubset(ThreeImageModel(), {1, 2, 99});
  ASSERT_EQ(subset.images.size(), 2u);
  EXPECT_EQ(subset.cameras.size(), 1u);   // camera 2 only served image 3
  ASSERT_EQ(subset.points3D.size(), 2u);  // 11 keeps one observation: dropped
  EXPECT_EQ(subset.points3D.at(10).track.size(), 2u);
  EXPECT_EQ(subset.points3D.count(11), 0u);
  EXPECT_EQ(subset.images.at(2).points2D[1].point3D_id, kColmapNoPoint3D);
  EXPECT_EQ(subset.images.at(2).points2D[2].point3D_id, 12);
  // Every remaining link goes both ways.
  for (const auto& [id, point] : subset.points3D) {
    for (const ColmapTrackElement& element : point.track) {
      EXPECT_EQ(subset.images.at(element.image_id)
                    .points2D.at(element.point2D_idx)
                    .point3D_id,
                id);
    }
  }
}

TEST(ColmapModelSubset, MinimumTrackLengthOfOneKeepsSingleObservations) {
  const ColmapModel subset = ColmapModelSubset(ThreeImageModel(), {3}, 1);
  EXPECT_EQ(subset.points3D.size(), 2u);  // 10 and 11, one observation each
  EXPECT_EQ(subset.images.at(3).points2D[0].point3D_id, 10);
}

}  // namespace
}  // namespace odomcal
