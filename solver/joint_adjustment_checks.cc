// The joint adjustment's checks of its options and of its problem, and its
// status names (joint_adjustment.h).
#include "odomcal/solver/joint_adjustment.h"
#include "odomcal/solver/joint_adjustment_cost.h"
#include "odomcal/solver/joint_adjustment_internal.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace odomcal {
namespace internal {

std::string CheckProblem(const JointAdjustmentProblem& problem) {
  if (problem.images.empty()) return "no images";
  if (problem.links.empty()) return "no odometry links";
  for (size_t c = 0; c < problem.cameras.size(); ++c) {
    const JointCamera& camera = problem.cameras[c];
    if (static_cast<int>(camera.params.size()) !=
        ProjectionNumParams(camera.model)) {
      return "camera " + std::to_string(c) + ": " +
             std::to_string(camera.params.size()) + " parameters for " +
             ProjectionModelName(camera.model);
    }
    for (const double value : camera.params) {
      if (!std::isfinite(value)) {
        return "camera " + std::to_string(c) + ": a non-finite parameter";
      }
    }
  }
  const int num_mounts = 1 + static_cast<int>(problem.other_mounts.size());
  std::vector<char> mount_seen(num_mounts, 0);
  for (size_t i = 0; i < problem.images.size(); ++i) {
    const JointImage& image = problem.images[i];
    if (image.camera < 0 ||
        image.camera >= static_cast<int>(problem.cameras.size())) {
      return "image " + std::to_string(i) + ": no camera " +
             std::to_string(image.camera);
    }
    if (image.mount < 0 || image.mount >= num_mounts) {
      return "image " + std::to_string(i) + ": no mount " +
             std::to_string(image.mount);
    }
    mount_seen[image.mount] = 1;
  }
  for (int m = 0; m < num_mounts; ++m) {
    if (!mount_seen[m]) return "mount " + std::to_string(m) + " has no image";
  }
  const int num_images = static_cast<int>(problem.images.size());
  const int num_points = static_cast<int>(problem.points.size());
  for (const JointObservation& observation : problem.observations) {
    if (observation.image < 0 || observation.image >= num_images ||
        observation.point < 0 || observation.point >= num_points ||
        !observation.pixel.allFinite()) {
      return "an observation names a missing image or point, or a "
             "non-finite pixel";
    }
  }
  const bool se3 = problem.motion_model == RobotMotionModel::kSE3;
  for (const OdometryLink& link : problem.links) {
    if (link.image_i < 0 || link.image_i >= num_images || link.image_j < 0 ||
        link.image_j >= num_images || link.image_i == link.image_j) {
      return "an odometry link names a missing image or one image twice";
    }
    if (se3) {
      Eigen::Matrix<double, 6, 6> unused;
      if (!link.motion_3d) {
        return "an odometry link without the whole motion, which the SE(3) "
               "robot poses need";
      }
      if (!IsFinite(link.motion_3d->odom_i_from_odom_j) ||
          !SqrtInformation(link.motion_3d->covariance, &unused)) {
        return "an odometry link's SE(3) motion is not finite or its "
               "covariance not positive definite";
      }
      continue;
    }
    Eigen::Matrix3d unused;
    if (!SqrtInformation(link.covariance, &unused)) {
      return "an odometry link's covariance is not positive definite";
    }
  }
  for (const JointImage& image : problem.images) {
    if (!IsFinite(image.origin_from_odom)) {
      return "an image's starting pose is not finite";
    }
  }
  if (se3 && problem.systematics) {
    return "the odometry's systematics are refined on a planar log only, "
           "not with SE(3) robot poses";
  }
  if (!IsFinite(problem.odom_from_cam)) return "a non-finite extrinsic";
  for (const Rigid3d& mount : problem.other_mounts) {
    if (!IsFinite(mount)) return "a non-finite extrinsic";
  }
  if (problem.systematics) {
    for (const OdometryLink& link : problem.links) {
      if (!link.samples) {
        return "an odometry link without the logged odometry, which the "
               "refinement of the odometry's systematics needs";
      }
    }
  }
  return "";
}

}  // namespace internal

void JointAdjustmentOptions::Check() const {
  const auto positive = [](double value, const char* name) {
    if (!(value > 0.0) || !std::isfinite(value)) {
      throw std::invalid_argument(std::string(name) + " must be positive");
    }
  };
  positive(pixel_sigma, "pixel_sigma");
  positive(loss_scale, "loss_scale");
  positive(max_reprojection_sigmas, "max_reprojection_sigmas");
  positive(ground_tilt_rate_deg_per_m, "ground_tilt_rate_deg_per_m");
  if (!(min_triangulation_angle_deg >= 0.0 &&
        min_triangulation_angle_deg < 90.0)) {
    throw std::invalid_argument(
        "min_triangulation_angle_deg must be in [0, 90)");
  }
  if (max_num_iterations < 1) {
    throw std::invalid_argument("max_num_iterations must be at least 1");
  }
  if (num_threads < 1) {
    throw std::invalid_argument("num_threads must be at least 1");
  }
}

const char* ToString(RobotMotionModel model) {
  switch (model) {
    case RobotMotionModel::kPlanar:
      return "planar";
    case RobotMotionModel::kSE3:
      return "se3";
    case RobotMotionModel::kOnGround:
      return "on_ground";
  }
  return "unknown";
}

const char* ToString(JointAdjustmentStatus status) {
  switch (status) {
    case JointAdjustmentStatus::kSuccess:
      return "success";
    case JointAdjustmentStatus::kInvalidInput:
      return "invalid_input";
    case JointAdjustmentStatus::kNoConvergence:
      return "no_convergence";
    case JointAdjustmentStatus::kSingular:
      return "singular";
  }
  return "unknown";
}

}  // namespace odomcal
