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
  // The pose of the robot at a planar pose on the ground: its height and
  // its pitch and roll from the ground's slope there.
  const double slope = std::tan(options.ground_slope_deg * kDegToRad);
  constexpr double kWavelength = 20.0;
  const double amplitude = slope * kWavelength / (2.0 * kPi);
  // The waves' phases vary with the seed (their own generator: the other
  // draws stay those of a level scene).
  std::mt19937 ground_random(options.seed + 7919u);
  std::uniform_real_distribution<double> phase(0.0, 2.0 * kPi);
  const double phase_x0 = phase(ground_random);
  const double phase_y0 = phase(ground_random);
  const auto on_ground = [&](const PlanarPose& planar) {
    const double phase_x = 2.0 * kPi * planar.x / kWavelength + phase_x0;
    const double phase_y = 2.0 * kPi * planar.y / kWavelength + phase_y0;
    const double z = amplitude * (std::sin(phase_x) + 0.8 * std::cos(phase_y));
    const double gx = slope * std::cos(phase_x);
    const double gy = -0.8 * slope * std::sin(phase_y);
    // The odometry frame on the ground: z its normal, x the heading
    // along it.
    const Eigen::Vector3d up = Eigen::Vector3d(-gx, -gy, 1.0).normalized();
    const double c = std::cos(planar.yaw_rad);
    const double s = std::sin(planar.yaw_rad);
    const Eigen::Vector3d ahead =
        Eigen::Vector3d(c, s, c * gx + s * gy).normalized();
    Eigen::Matrix3d rotation;
    rotation << ahead, up.cross(ahead), up;
    return Rigid3d{Eigen::Quaterniond(rotation),
                   Eigen::Vector3d(planar.x, planar.y, z)};
  };
  PlanarPose pose;
  // Halfway between consecutive poses in time: the rear camera's.
  std::vector<PlanarPose> rear_poses;
  for (int i = 0; i < num_images; ++i) {
    scene.poses.push_back(on_ground(pose));
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
  for (const Rigid3d& p : scene.poses) {
    for (int k = 0; k < per_image; ++k) {
      const double ahead = 1.0 + 6.0 * uniform(random);
      const double side = (uniform(random) - 0.5) * 10.0;
      const double height = -0.3 + 2.5 * uniform(random);
      scene.points.push_back(p * Eigen::Vector3d(ahead, side, height));
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
  // A starting pose: the truth drifted, turned by 0.1 deg about each axis.
  const auto start_of = [&](const Rigid3d& truth, double fraction) {
    const Eigen::Vector3d turn =
        0.002 * Eigen::Vector3d(normal(random), normal(random), normal(random));
    return Rigid3d{
        Eigen::AngleAxisd(turn.norm(), turn.normalized()) * truth.rotation,
        drifted(truth.translation, fraction)};
  };
  for (int i = 0; i < num_images; ++i) {
    const double fraction = static_cast<double>(i) / num_images;
    JointImage image;
    image.origin_from_odom = start_of(scene.poses[i], fraction);
    problem.images.push_back(image);
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
    observe(i, i, Inverse(scene.poses[i] * scene.odom_from_cam), 0);
  }
  if (options.se3_odometry) problem.motion_model = RobotMotionModel::kSE3;
  // The link of the odometry from pose a to pose b, with its noise: the
  // planar part of the motion, or with se3_odometry the whole of it.
  const auto link_between = [&](int image_i,
                                int image_j,
                                const Rigid3d& a,
                                const Rigid3d& b) {
    const Rigid3d truth = Inverse(a) * b;
    const PlanarPose motion = PlanarFromRigid(truth);
    const double length = truth.translation.norm();
    const double xy_sigma = 0.002 + 0.01 * length;
    const double yaw_sigma = 0.2 * kDegToRad + 0.01 * std::abs(motion.yaw_rad);
    OdometryLink link;
    link.image_i = image_i;
    link.image_j = image_j;
    if (options.se3_odometry) {
      const double tilt_sigma =
          0.05 * kDegToRad + 0.01 * std::abs(motion.yaw_rad);
      Eigen::Matrix<double, 6, 1> sigmas;
      sigmas << tilt_sigma, tilt_sigma, yaw_sigma, xy_sigma, xy_sigma, xy_sigma;
      Eigen::Matrix<double, 6, 1> error;
      for (int k = 0; k < 6; ++k) error[k] = sigmas[k] * normal(random);
      const Eigen::Vector3d phi = error.head<3>();
      OdometryMotion3d measured;
      measured.odom_i_from_odom_j = {
          Eigen::AngleAxisd(phi.norm(),
                            phi.norm() > 0.0 ? Eigen::Vector3d(phi.normalized())
                                             : Eigen::Vector3d::UnitZ()) *
              truth.rotation,
          truth.translation + error.tail<3>()};
      measured.covariance = sigmas.cwiseAbs2().asDiagonal();
      link.motion_3d = measured;
    }
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
    std::vector<Rigid3d> rear_truth;
    rear_truth.reserve(rear_poses.size());
    for (const PlanarPose& rear : rear_poses) {
      rear_truth.push_back(on_ground(rear));
    }
    for (size_t r = 0; r < rear_truth.size(); ++r) {
      const double fraction = (static_cast<double>(r) + 0.5) / num_images;
      JointImage image;
      image.camera = 1;
      image.mount = 1;
      image.origin_from_odom = start_of(rear_truth[r], fraction);
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
    for (size_t r = 0; r < rear_truth.size(); ++r) {
      observe(rear_first + static_cast<int>(r),
              static_cast<int>(r),
              Inverse(rear_truth[r] * scene.rear_odom_from_cam),
              rear_point_offset);
    }
    for (int i = 0; i + 1 < num_images; ++i) {
      link_between(i, rear_first + i, scene.poses[i], rear_truth[i]);
      link_between(rear_first + i, i + 1, rear_truth[i], scene.poses[i + 1]);
    }
    scene.poses.insert(scene.poses.end(), rear_truth.begin(), rear_truth.end());
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
