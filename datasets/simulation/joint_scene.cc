#include "odomcal/datasets/simulation/joint_scene.h"

#include "odomcal/solver/angles.h"
#include "odomcal/solver/camera_projection.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <random>

namespace odomcal {

JointScene SimulateJointScene(const JointSceneOptions& options) {
  std::mt19937 random(options.seed);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  JointScene scene;
  scene.odom_from_cam.rotation =
      Eigen::AngleAxisd(3.0 * kDegToRad, Eigen::Vector3d::UnitZ()) *
      Eigen::AngleAxisd(-2.0 * kDegToRad, Eigen::Vector3d::UnitY()) *
      Eigen::AngleAxisd(1.0 * kDegToRad, Eigen::Vector3d::UnitX()) *
      Eigen::Quaterniond(
          (Eigen::Matrix3d() << 0, 0, 1, -1, 0, 0, 0, -1, 0).finished());
  scene.odom_from_cam.translation = Eigen::Vector3d(0.3, -0.05, 0.5);
  scene.rear_odom_from_cam.rotation =
      Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitZ()) *
      Eigen::AngleAxisd(5.0 * kDegToRad, Eigen::Vector3d::UnitY()) *
      scene.odom_from_cam.rotation;
  scene.rear_odom_from_cam.translation = Eigen::Vector3d(-0.4, 0.1, 0.6);
  const int num_images = options.num_images;
  PlanarPose pose;
  // Halfway between consecutive poses in time: the rear camera's.
  std::vector<PlanarPose> rear_poses;
  for (int i = 0; i < num_images; ++i) {
    scene.poses.push_back(pose);
    const double turn = 0.25 * std::sin(0.12 * i);
    if (i + 1 < num_images) {
      PlanarPose half = pose;
      half.x += 0.125 * std::cos(pose.yaw_rad + 0.25 * turn);
      half.y += 0.125 * std::sin(pose.yaw_rad + 0.25 * turn);
      half.yaw_rad += 0.5 * turn;
      rear_poses.push_back(half);
    }
    pose.x += 0.25 * std::cos(pose.yaw_rad + 0.5 * turn);
    pose.y += 0.25 * std::sin(pose.yaw_rad + 0.5 * turn);
    pose.yaw_rad += turn;
  }
  const int per_image = options.points_per_image;
  for (const PlanarPose& p : scene.poses) {
    for (int k = 0; k < per_image; ++k) {
      const double ahead = 1.0 + 6.0 * uniform(random);
      const double side = (uniform(random) - 0.5) * 10.0;
      const double height = -0.3 + 2.5 * uniform(random);
      scene.points.push_back(p.ToRigid3d() *
                             Eigen::Vector3d(ahead, side, height));
    }
  }
  JointAdjustmentProblem& problem = scene.problem;
  problem.cameras.push_back(
      {ProjectionModel::kSimpleRadial, {500.0, 320.5, 240.5, -0.05}});
  const auto drifted = [&](const Eigen::Vector3d& x, double fraction) {
    return Eigen::Vector3d(x.x() * (1.0 + options.drift * fraction),
                           x.y() * (1.0 + options.drift * fraction),
                           x.z());
  };
  for (int i = 0; i < num_images; ++i) {
    const double fraction = static_cast<double>(i) / num_images;
    const Eigen::Vector3d xy = drifted(
        Eigen::Vector3d(scene.poses[i].x, scene.poses[i].y, 0.0), fraction);
    problem.images.push_back(
        {0, {xy.x(), xy.y(), scene.poses[i].yaw_rad + 0.002 * normal(random)}});
  }
  for (size_t k = 0; k < scene.points.size(); ++k) {
    // The drift of the image the point was placed ahead of.
    const size_t image = k / static_cast<size_t>(per_image);
    const double fraction =
        static_cast<double>(image) / static_cast<double>(num_images);
    problem.points.push_back(
        drifted(scene.points[k], fraction) +
        0.01 * Eigen::Vector3d(normal(random), normal(random), normal(random)));
  }
  problem.odom_from_cam.rotation =
      Eigen::AngleAxisd(0.5 * kDegToRad,
                        Eigen::Vector3d(1.0, -1.0, 1.0).normalized()) *
      scene.odom_from_cam.rotation;
  problem.odom_from_cam.translation =
      scene.odom_from_cam.translation + Eigen::Vector3d(0.02, -0.01, 0.0);
  // Within the 640 x 480 image, 0.5 to 12 m ahead: 12 m is 48 images of
  // travel, so only the points of images within 50 of this one can be in
  // view (linear in the images). `first_point`: where the copies of the
  // points the camera sees start.
  constexpr int kViewWindow = 50;
  const std::vector<double> params = problem.cameras[0].params;
  const auto observe = [&](int image,
                           int near_image,
                           const Rigid3d& cam_from_origin,
                           int first_point) {
    const Eigen::Vector2d image_shift =
        options.image_shift_px *
        Eigen::Vector2d(normal(random), normal(random));
    const int first = std::max(0, near_image - kViewWindow) * per_image;
    const int last =
        std::min(num_images, near_image + kViewWindow + 1) * per_image;
    for (int k = first; k < last; ++k) {
      const Eigen::Vector3d in_cam = cam_from_origin * scene.points[k];
      if (in_cam.z() < 0.5 || in_cam.z() > 12.0) continue;
      Eigen::Vector2d pixel;
      if (!ProjectToPixel<ProjectionModel::kSimpleRadial>(
              params.data(), in_cam.data(), pixel.data()) ||
          pixel.x() < 0.0 || pixel.x() > 640.0 || pixel.y() < 0.0 ||
          pixel.y() > 480.0) {
        continue;
      }
      pixel +=
          image_shift +
          options.pixel_sigma * Eigen::Vector2d(normal(random), normal(random));
      if (uniform(random) < options.outlier_fraction) {
        pixel += Eigen::Vector2d(40.0 * normal(random), 40.0 * normal(random));
      }
      problem.observations.push_back({image, first_point + k, pixel});
    }
  };
  for (int i = 0; i < num_images; ++i) {
    observe(i, i, Inverse(scene.poses[i].ToRigid3d() * scene.odom_from_cam), 0);
  }
  // The link of the odometry from pose a to pose b, with its noise.
  const auto link_between =
      [&](int image_i, int image_j, const PlanarPose& a, const PlanarPose& b) {
        const PlanarPose motion =
            PlanarFromRigid(Inverse(a.ToRigid3d()) * b.ToRigid3d());
        const double length = std::hypot(motion.x, motion.y);
        const double xy_sigma = 0.002 + 0.01 * length;
        const double yaw_sigma =
            0.2 * kDegToRad + 0.01 * std::abs(motion.yaw_rad);
        OdometryLink link;
        link.image_i = image_i;
        link.image_j = image_j;
        link.covariance =
            Eigen::Vector3d(
                xy_sigma * xy_sigma, xy_sigma * xy_sigma, yaw_sigma * yaw_sigma)
                .asDiagonal();
        link.odom_i_from_odom_j = {motion.x + xy_sigma * normal(random),
                                   motion.y + xy_sigma * normal(random),
                                   motion.yaw_rad + yaw_sigma * normal(random)};
        problem.links.push_back(link);
      };
  if (options.rear_camera) {
    // Its images (camera 1, mount 1), its points (copies unless shared),
    // its observations, then the links through both cameras' images in
    // time order.
    problem.cameras.push_back(problem.cameras[0]);
    const int rear_first = num_images;
    for (size_t r = 0; r < rear_poses.size(); ++r) {
      const double fraction = (static_cast<double>(r) + 0.5) / num_images;
      const Eigen::Vector3d xy = drifted(
          Eigen::Vector3d(rear_poses[r].x, rear_poses[r].y, 0.0), fraction);
      JointImage image;
      image.camera = 1;
      image.mount = 1;
      image.origin_from_odom = {
          xy.x(), xy.y(), rear_poses[r].yaw_rad + 0.002 * normal(random)};
      problem.images.push_back(image);
    }
    int rear_point_offset = 0;
    if (!options.rear_shares_points) {
      rear_point_offset = static_cast<int>(problem.points.size());
      for (size_t k = 0; k < scene.points.size(); ++k) {
        const size_t image = k / static_cast<size_t>(per_image);
        const double fraction =
            static_cast<double>(image) / static_cast<double>(num_images);
        problem.points.push_back(drifted(scene.points[k], fraction) +
                                 0.01 * Eigen::Vector3d(normal(random),
                                                        normal(random),
                                                        normal(random)));
      }
    }
    problem.other_mounts.push_back(
        {Eigen::AngleAxisd(0.5 * kDegToRad,
                           Eigen::Vector3d(1.0, 1.0, -1.0).normalized()) *
             scene.rear_odom_from_cam.rotation,
         scene.rear_odom_from_cam.translation +
             Eigen::Vector3d(-0.02, 0.01, 0.0)});
    for (size_t r = 0; r < rear_poses.size(); ++r) {
      observe(rear_first + static_cast<int>(r),
              static_cast<int>(r),
              Inverse(rear_poses[r].ToRigid3d() * scene.rear_odom_from_cam),
              rear_point_offset);
    }
    for (int i = 0; i + 1 < num_images; ++i) {
      link_between(i, rear_first + i, scene.poses[i], rear_poses[i]);
      link_between(rear_first + i, i + 1, rear_poses[i], scene.poses[i + 1]);
    }
    scene.poses.insert(scene.poses.end(), rear_poses.begin(), rear_poses.end());
  } else {
    for (int i = 0; i + 1 < num_images; ++i) {
      link_between(i, i + 1, scene.poses[i], scene.poses[i + 1]);
    }
  }
  // The gauge image starts at its true pose, as the caller's first image
  // starts at its odometry pose.
  problem.images[0].origin_from_odom = scene.poses[0];
  return scene;
}

}  // namespace odomcal
