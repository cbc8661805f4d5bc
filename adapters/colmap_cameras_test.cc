#include "odomcal/adapters/colmap_cameras.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace odomcal {
namespace {

std::vector<ColmapImageCamera> Images(const std::vector<std::string>& names,
                                      const std::vector<uint32_t>& cameras) {
  std::vector<ColmapImageCamera> images;
  for (size_t k = 0; k < names.size(); ++k) {
    images.push_back({cameras[k], names[k]});
  }
  return images;
}

TEST(ColmapCameras, OneCameraIdIsOneCamera) {
  const ColmapProjectCameras cameras = GroupColmapImagesIntoCameras(
      Images({"a/1.png", "b/2.png", "3.png"}, {1, 1, 1}));
  EXPECT_EQ(cameras.grouping, ColmapCameraGrouping::kSingleCamera);
  ASSERT_EQ(cameras.cameras.size(), 1u);
  EXPECT_FALSE(cameras.IsRig());
  EXPECT_EQ(cameras.cameras[0].num_images, 3);
}

TEST(ColmapCameras, SubFoldersNameTheCamerasAndGatherTheirIds) {
  // COLMAP gave every image of the rear folder intrinsics of its own.
  const ColmapProjectCameras cameras =
      GroupColmapImagesIntoCameras(Images({"rig/rear/1.png",
                                           "front/1.png",
                                           "front/2.png",
                                           "rig/rear/2.png",
                                           "front/1.png"},
                                          {2, 1, 1, 3, 1}));
  EXPECT_EQ(cameras.grouping, ColmapCameraGrouping::kBySubFolder);
  ASSERT_EQ(cameras.cameras.size(), 2u);
  EXPECT_EQ(cameras.cameras[0].name, "front");
  EXPECT_EQ(cameras.cameras[0].camera_ids, (std::set<uint32_t>{1}));
  EXPECT_EQ(cameras.cameras[0].num_images, 2);  // front/1.png counted once
  EXPECT_EQ(cameras.cameras[1].name, "rig_rear");
  EXPECT_EQ(cameras.cameras[1].camera_ids, (std::set<uint32_t>{2, 3}));
}

TEST(ColmapCameras, FolderNamesThatCollideAreMadeUnique) {
  const ColmapProjectCameras cameras =
      GroupColmapImagesIntoCameras(Images({"a b/1.png", "a_b/1.png"}, {1, 2}));
  ASSERT_EQ(cameras.cameras.size(), 2u);
  EXPECT_NE(cameras.cameras[0].name, cameras.cameras[1].name);
}

TEST(ColmapCameras, CameraIdsWithoutFoldersAreCameras) {
  const ColmapProjectCameras cameras = GroupColmapImagesIntoCameras(
      Images({"l1.png", "r1.png", "l2.png", "r2.png", "l3.png", "r3.png"},
             {1, 2, 1, 2, 1, 2}));
  EXPECT_EQ(cameras.grouping, ColmapCameraGrouping::kByCameraId);
  ASSERT_EQ(cameras.cameras.size(), 2u);
  EXPECT_EQ(cameras.cameras[0].name, "camera_1");
  EXPECT_EQ(cameras.cameras[1].name, "camera_2");
  EXPECT_EQ(cameras.cameras[1].num_images, 3);
}

// A camera shared by two folders: the folders are not the cameras.
TEST(ColmapCameras, ACameraIdAcrossFoldersGroupsByCameraId) {
  const ColmapProjectCameras cameras =
      GroupColmapImagesIntoCameras(Images({"day1/1.png",
                                           "day2/1.png",
                                           "day1/2.png",
                                           "x/3.png",
                                           "x/4.png",
                                           "x/5.png"},
                                          {1, 1, 1, 2, 2, 2}));
  EXPECT_EQ(cameras.grouping, ColmapCameraGrouping::kByCameraId);
  ASSERT_EQ(cameras.cameras.size(), 2u);
}

TEST(ColmapCameras, IntrinsicsPerImageAreOneCamera) {
  const ColmapProjectCameras cameras = GroupColmapImagesIntoCameras(
      Images({"1.png", "2.png", "3.png", "4.png"}, {1, 2, 3, 4}));
  EXPECT_EQ(cameras.grouping, ColmapCameraGrouping::kOnePerImage);
  ASSERT_EQ(cameras.cameras.size(), 1u);
  EXPECT_EQ(cameras.cameras[0].camera_ids.size(), 4u);
}

}  // namespace
}  // namespace odomcal
