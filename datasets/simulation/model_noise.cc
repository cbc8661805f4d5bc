#include "odomcal/datasets/simulation/model_noise.h"

#include "odomcal/adapters/association.h"
#include "odomcal/solver/angles.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace odomcal {
namespace {

// The pose of the log at `stamp` (linear in time between samples).
Rigid3d PoseAt(const Trajectory& odometry, int64_t stamp) {
  InterpolationFailure why;
  const auto pose = InterpolateOdometry(odometry, stamp, 1e9, &why);
  if (!pose) throw std::invalid_argument("a time outside the odometry");
  return *pose;
}

// A planar motion: yaw about z, then x, y.
Rigid3d NoiseMotion(double yaw_rad, double x_m, double y_m) {
  return Rigid3d(YawRotation(yaw_rad), Eigen::Vector3d(x_m, y_m, 0.0));
}

}  // namespace

Trajectory WithModelOdometryNoise(const Trajectory& odometry,
                                  const std::vector<int64_t>& image_stamps_ns,
                                  const NoiseModel& noise,
                                  double factor,
                                  uint64_t seed) {
  std::mt19937_64 random(seed);
  std::normal_distribution<double> normal;
  // Per interval k (image k to k + 1): the noise motion, and the measured
  // pose at image k.
  std::vector<Eigen::Vector3d> interval_noise;  // yaw, x, y
  std::vector<Rigid3d> measured_at_image;
  Rigid3d measured;
  for (size_t k = 0; k < image_stamps_ns.size(); ++k) {
    const Rigid3d truth = PoseAt(odometry, image_stamps_ns[k]);
    if (k == 0) measured = truth;
    measured_at_image.push_back(measured);
    if (k + 1 == image_stamps_ns.size()) break;
    const Rigid3d motion =
        Inverse(truth) * PoseAt(odometry, image_stamps_ns[k + 1]);
    const double yaw_deg =
        std::abs(LogRotation(motion.rotation).z()) * kRadToDeg;
    const double length_m = motion.translation.norm();
    const double yaw_sigma_rad =
        factor * kDegToRad *
        (noise.odom_yaw_sigma_deg + noise.odom_yaw_sigma_rel * yaw_deg);
    const double translation_sigma_m =
        factor * (noise.odom_translation_sigma_m +
                  noise.odom_translation_sigma_rel * length_m);
    const Eigen::Vector3d n(yaw_sigma_rad * normal(random),
                            translation_sigma_m * normal(random),
                            translation_sigma_m * normal(random));
    interval_noise.push_back(n);
    measured = measured * motion * NoiseMotion(n(0), n(1), n(2));
  }
  Trajectory noisy = odometry;
  for (StampedPose& pose : noisy.poses) {
    const int64_t t = pose.stamp_ns;
    if (image_stamps_ns.empty() || t < image_stamps_ns.front()) continue;
    // The interval holding t (the last image's pose continues beyond it).
    const auto next =
        std::upper_bound(image_stamps_ns.begin(), image_stamps_ns.end(), t);
    const size_t k = static_cast<size_t>(next - image_stamps_ns.begin()) - 1;
    const int64_t start = image_stamps_ns[k];
    const Rigid3d since_image =
        Inverse(PoseAt(odometry, start)) * pose.world_from_sensor;
    Rigid3d spread;
    if (k < interval_noise.size()) {
      const double fraction =
          static_cast<double>(t - start) /
          static_cast<double>(image_stamps_ns[k + 1] - start);
      const Eigen::Vector3d n = fraction * interval_noise[k];
      spread = NoiseMotion(n(0), n(1), n(2));
    }
    pose.world_from_sensor = measured_at_image[k] * since_image * spread;
  }
  return noisy;
}

Trajectory ModelNoisyReconstruction(const Trajectory& true_odometry,
                                    const std::vector<int64_t>& capture_ns,
                                    const std::vector<int64_t>& stamps_ns,
                                    const Rigid3d& odom_from_cam,
                                    double metres_per_unit,
                                    const NoiseModel& noise,
                                    double factor,
                                    uint64_t seed) {
  if (capture_ns.size() != stamps_ns.size()) {
    throw std::invalid_argument("capture and recorded times differ in number");
  }
  std::vector<Rigid3d> truth;
  std::vector<double> steps_m;
  for (const int64_t capture : capture_ns) {
    truth.push_back(PoseAt(true_odometry, capture) * odom_from_cam);
    if (truth.size() > 1) {
      steps_m.push_back(
          (truth.back().translation - truth[truth.size() - 2].translation)
              .norm());
    }
  }
  double median_step_m = 0.0;
  if (!steps_m.empty()) {
    std::nth_element(
        steps_m.begin(), steps_m.begin() + steps_m.size() / 2, steps_m.end());
    median_step_m = steps_m[steps_m.size() / 2];
  }
  const double rotation_sigma_rad =
      factor * noise.cam_rotation_sigma_deg * kDegToRad / std::sqrt(2.0);
  const double position_sigma_m =
      factor * noise.cam_translation_sigma_rel * median_step_m / std::sqrt(2.0);
  std::mt19937_64 random(seed);
  std::normal_distribution<double> normal;
  const auto draw = [&] {
    return Eigen::Vector3d(normal(random), normal(random), normal(random));
  };
  Trajectory camera;
  camera.source = "reconstruction";
  for (size_t k = 0; k < truth.size(); ++k) {
    Rigid3d world_from_cam = truth[k];
    world_from_cam.rotation =
        (world_from_cam.rotation * ExpRotation(rotation_sigma_rad * draw()))
            .normalized();
    world_from_cam.translation =
        (world_from_cam.translation + position_sigma_m * draw()) /
        metres_per_unit;
    camera.poses.push_back({stamps_ns[k], world_from_cam});
  }
  return camera;
}

}  // namespace odomcal
