#include "odomcal/plugin/colmap/fold_reposing.h"

#include "odomcal/adapters/test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace odomcal {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int64_t kOffsetNs = 20'000'000;  // odometry = camera + 20 ms
constexpr double kMetresPerUnit = 0.5;

Rigid3d Planar(double x, double y, double yaw) {
  return Rigid3d(
      Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ())),
      Eigen::Vector3d(x, y, 0.0));
}

// A drive that turns left, then right, sampled at 10 Hz, with a camera
// looking forward from 0.25 m ahead of the odometry frame, and a
// reconstruction whose frame is an arbitrary similarity of the odometry's:
// images every 5th sample, at the samples' times minus the clock offset.
struct FoldScene {
  Trajectory odometry;
  Rigid3d odom_from_cam;
  ColmapModel truth;  // the images where the odometry puts them
  ColmapSegment segment;

  FoldScene() {
    odometry.planar = true;
    double x = 0.0, y = 0.0, yaw = 0.0;
    for (int i = 0; i <= 200; ++i) {
      odometry.poses.push_back({int64_t{100'000'000} * i, Planar(x, y, yaw)});
      const double turn = i < 100 ? 0.02 : -0.03;
      x += 0.05 * std::cos(yaw + turn / 2);
      y += 0.05 * std::sin(yaw + turn / 2);
      yaw += turn;
    }
    odom_from_cam = Rigid3d(Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5),
                            Eigen::Vector3d(0.25, 0.05, 0.4));
    const Rigid3d world_from_origin(
        Eigen::Quaterniond(
            Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized())),
        Eigen::Vector3d(3.0, -1.0, 2.0));
    truth.cameras[1] = MakeColmapCamera(
        1, ColmapCameraModel::kPinhole, 320, 240, {260, 260, 160, 120});
    segment.sub_model = "0";
    for (int i = 0; i <= 200; i += 5) {
      const uint32_t id = static_cast<uint32_t>(i + 1);
      Rigid3d origin_from_cam =
          odometry.poses[i].world_from_sensor * odom_from_cam;
      origin_from_cam.translation /= kMetresPerUnit;
      Rigid3d world_from_origin_units = world_from_origin;
      world_from_origin_units.translation /= kMetresPerUnit;
      const Rigid3d world_from_cam = world_from_origin_units * origin_from_cam;
      ColmapImage image;
      image.image_id = id;
      image.camera_id = 1;
      image.name = "image_" + std::to_string(1000 + i) + ".png";
      image.cam_from_world = Inverse(world_from_cam);
      image.points2D.push_back({Eigen::Vector2d(10, 20), 7});
      truth.images[id] = image;
      segment.trajectory.poses.push_back(
          {odometry.poses[i].stamp_ns - kOffsetNs, world_from_cam});
      segment.image_names.push_back(image.name);
      segment.image_ids.push_back(id);
    }
    ColmapPoint3D point;
    point.point3D_id = 7;
    point.track.push_back({1, 0});
    truth.points3D[7] = point;
  }

  // The truth with every image after sample `anchor` turned 3 deg and its
  // centre moved 1 unit: a fold.
  ColmapModel Folded(int anchor) const {
    ColmapModel model = truth;
    for (auto& [id, image] : model.images) {
      if (static_cast<int>(id) - 1 <= anchor) continue;
      image.cam_from_world.rotation =
          Eigen::AngleAxisd(3.0 * kPi / 180.0, Eigen::Vector3d::UnitX()) *
          image.cam_from_world.rotation;
      image.cam_from_world.translation += Eigen::Vector3d(1.0, 0.0, 0.0);
    }
    return model;
  }

  FoldToRepose Fold(int anchor) const {
    FoldToRepose fold;
    fold.first_stamp_ns = odometry.poses[anchor].stamp_ns;
    fold.camera_time_offset_ns = kOffsetNs;
    fold.odom_from_cam = odom_from_cam;
    fold.metres_per_unit = kMetresPerUnit;
    fold.max_odometry_gap_s = 0.25;
    return fold;
  }
};

double PoseDifference(const Rigid3d& a, const Rigid3d& b) {
  return std::max(RotationAngle(a.rotation.conjugate() * b.rotation),
                  (a.translation - b.translation).norm());
}

TEST(FoldReposing, ImagesAfterTheAnchorGetTheirTruePoses) {
  const FoldScene scene;
  const int anchor = 100;
  const auto reposed = ReposeFoldFromOdometry(
      scene.Folded(anchor), scene.segment, scene.odometry, scene.Fold(anchor));
  ASSERT_TRUE(reposed.has_value());
  EXPECT_EQ(reposed->anchor_image, "image_1100.png");
  EXPECT_EQ(reposed->num_reposed, 20);
  ASSERT_EQ(reposed->reposed_image_ids.size(), 20u);
  EXPECT_EQ(reposed->reposed_image_ids.front(), 106u);
  EXPECT_EQ(reposed->reposed_image_ids.back(), 201u);
  EXPECT_EQ(reposed->num_left_out, 0);
  ASSERT_EQ(reposed->model.images.size(), scene.truth.images.size());
  for (const auto& [id, image] : reposed->model.images) {
    EXPECT_LT(PoseDifference(image.cam_from_world,
                             scene.truth.images.at(id).cam_from_world),
              1e-9)
        << image.name;
    // The fold's points go: they are to be triangulated again.
    ASSERT_EQ(image.points2D.size(), 1u);
    EXPECT_EQ(image.points2D[0].point3D_id, kColmapNoPoint3D);
  }
  EXPECT_TRUE(reposed->model.points3D.empty());
}

TEST(FoldReposing, ImagesBeforeTheAnchorStayWhereColmapPutThem) {
  const FoldScene scene;
  // Everything after sample 50 is wrong in the model; posing from sample
  // 150 on must leave 55-150 as they were (wrong), and fix the rest.
  const ColmapModel folded = scene.Folded(50);
  const auto reposed = ReposeFoldFromOdometry(
      folded, scene.segment, scene.odometry, scene.Fold(150));
  ASSERT_TRUE(reposed.has_value());
  EXPECT_EQ(reposed->num_reposed, 10);
  for (const auto& [id, image] : reposed->model.images) {
    const int sample = static_cast<int>(id) - 1;
    if (sample <= 150) {
      EXPECT_LT(PoseDifference(image.cam_from_world,
                               folded.images.at(id).cam_from_world),
                1e-12)
          << image.name;
    }
  }
  // Posed relative to the (wrong) anchor: relative motions are the truth's.
  const Rigid3d& anchor_pose = reposed->model.images.at(151).cam_from_world;
  const Rigid3d& later = reposed->model.images.at(201).cam_from_world;
  const Rigid3d& true_anchor = scene.truth.images.at(151).cam_from_world;
  const Rigid3d& true_later = scene.truth.images.at(201).cam_from_world;
  EXPECT_LT(PoseDifference(later * Inverse(anchor_pose),
                           true_later * Inverse(true_anchor)),
            1e-9);
}

TEST(FoldReposing, ImagesInAnOdometryGapAreLeftOut) {
  FoldScene scene;
  // No odometry from 14.6 s to 15.4 s: the image at 15 s has none.
  auto& poses = scene.odometry.poses;
  poses.erase(poses.begin() + 147, poses.begin() + 154);
  const auto reposed = ReposeFoldFromOdometry(
      scene.Folded(100), scene.segment, scene.odometry, scene.Fold(100));
  ASSERT_TRUE(reposed.has_value());
  EXPECT_EQ(reposed->num_left_out, 1);
  EXPECT_EQ(reposed->num_reposed, 19);
  EXPECT_EQ(reposed->model.images.count(151), 0u);
  EXPECT_EQ(reposed->model.images.size(), scene.truth.images.size() - 1);
}

TEST(FoldReposing, NothingWithoutAnImageAtTheFoldsStart) {
  const FoldScene scene;
  FoldToRepose fold = scene.Fold(100);
  fold.first_stamp_ns += 50'000'000;  // between two images
  EXPECT_FALSE(
      ReposeFoldFromOdometry(scene.truth, scene.segment, scene.odometry, fold)
          .has_value());
  // The last image as the anchor: nothing after it to pose.
  EXPECT_FALSE(ReposeFoldFromOdometry(
                   scene.truth, scene.segment, scene.odometry, scene.Fold(200))
                   .has_value());
  fold = scene.Fold(100);
  fold.metres_per_unit = 0.0;
  EXPECT_THROW(
      ReposeFoldFromOdometry(scene.truth, scene.segment, scene.odometry, fold),
      std::invalid_argument);
}

}  // namespace
}  // namespace odomcal
