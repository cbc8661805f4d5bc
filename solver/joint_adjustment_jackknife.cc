#include "odomcal/solver/joint_adjustment_jackknife.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>

namespace odomcal {
namespace {

// The problem without the images in [begin, end) of image_order (their
// feature observations and the links that touch them), nor the
// observations the full solve left out; started at the full solution, the
// links at the estimated level.
JointAdjustmentProblem WithoutBlock(const JointAdjustmentProblem& problem,
                                    const JointAdjustmentResult& full,
                                    const std::vector<int>& image_order,
                                    size_t begin,
                                    size_t end) {
  std::vector<int> new_index(problem.images.size(), 0);
  for (size_t n = begin; n < end; ++n) new_index[image_order[n]] = -1;
  JointAdjustmentProblem reduced;
  for (size_t i = 0; i < problem.images.size(); ++i) {
    if (new_index[i] < 0) continue;
    new_index[i] = static_cast<int>(reduced.images.size());
    JointImage image = problem.images[i];
    image.origin_from_odom = full.origin_from_odom[i];
    reduced.images.push_back(image);
  }
  reduced.cameras = full.cameras;
  reduced.points = full.points;
  for (size_t k = 0; k < problem.observations.size(); ++k) {
    JointObservation observation = problem.observations[k];
    if (new_index[observation.image] < 0 ||
        full.observation_error_px[k] < 0.0) {
      continue;
    }
    observation.image = new_index[observation.image];
    reduced.observations.push_back(observation);
  }
  const double factor = full.odometry_sigma_ratio * full.odometry_sigma_ratio;
  for (OdometryLink link : problem.links) {
    if (new_index[link.image_i] < 0 || new_index[link.image_j] < 0) continue;
    link.image_i = new_index[link.image_i];
    link.image_j = new_index[link.image_j];
    link.covariance *= factor;
    if (link.motion_3d) link.motion_3d->covariance *= factor;
    reduced.links.push_back(std::move(link));
  }
  reduced.motion_model = problem.motion_model;
  reduced.odom_from_cam = full.odom_from_cam;
  reduced.other_mounts = full.other_mounts;
  reduced.systematics = problem.systematics;
  if (reduced.systematics) {
    reduced.systematics->intrinsics = full.intrinsics;
    reduced.systematics->time_offset_change_s = full.time_offset_change_s;
  }
  return reduced;
}

}  // namespace

Eigen::VectorXd MountDeviations(const JointAdjustmentResult& reference,
                                const JointAdjustmentResult& estimate) {
  const auto mount = [](const JointAdjustmentResult& result, size_t m) {
    return m == 0 ? result.odom_from_cam : result.other_mounts.at(m - 1);
  };
  const size_t num_mounts = 1 + reference.other_mounts.size();
  Eigen::VectorXd deviation(5 * num_mounts);
  for (size_t m = 0; m < num_mounts; ++m) {
    const Rigid3d a = mount(reference, m);
    const Rigid3d b = mount(estimate, m);
    const Eigen::Index row = static_cast<Eigen::Index>(5 * m);
    deviation.segment<3>(row) = LogRotation(b.rotation * a.rotation.inverse());
    deviation.segment<2>(row + 3) = (b.translation - a.translation).head<2>();
  }
  return deviation;
}

void JointJackknifeOptions::Check() const {
  if (num_blocks < 0 || num_blocks == 1 || num_blocks == 2) {
    throw std::invalid_argument("num_blocks must be 0 (off) or at least 3");
  }
}

JointJackknife JackknifeJointExtrinsic(const JointAdjustmentProblem& problem,
                                       const JointAdjustmentOptions& options,
                                       const std::vector<int>& image_order,
                                       const JointJackknifeOptions& jackknife,
                                       JointAdjustmentResult* result) {
  jackknife.Check();
  options.Check();
  JointJackknife out;
  if (jackknife.num_blocks == 0) {
    out.reason = "off";
    return out;
  }
  if (!result->IsSuccess()) {
    out.reason = "the adjustment did not succeed";
    return out;
  }
  const size_t num_images = image_order.size();
  if (num_images != problem.images.size()) {
    out.reason = "the image order does not list every image";
    return out;
  }
  const size_t num_blocks = static_cast<size_t>(jackknife.num_blocks);
  if (num_images < 2 * num_blocks) {
    out.reason = std::to_string(num_images) + " images: fewer than 2 per block";
    return out;
  }
  const auto start = std::chrono::steady_clock::now();
  JointAdjustmentOptions resolve = options;
  resolve.pixel_sigma = result->pixel_sigma;
  resolve.estimate_odometry_noise = false;
  resolve.estimate_ground_tilt_rate = false;
  if (result->ground_tilt_rate_deg_per_m > 0.0) {
    resolve.ground_tilt_rate_deg_per_m = result->ground_tilt_rate_deg_per_m;
  }
  resolve.compute_covariance = false;
  // The full solve's outliers are already out; the rest stays in.
  resolve.max_reprojection_sigmas = std::numeric_limits<double>::max();
  std::vector<Eigen::VectorXd> deviations;
  std::string first_failure;
  for (size_t b = 0; b < num_blocks; ++b) {
    const size_t begin = b * num_images / num_blocks;
    const size_t end = (b + 1) * num_images / num_blocks;
    if (options.progress) {
      resolve.progress = [&options, &start, b, num_blocks](
                             const JointAdjustmentProgress& inner) {
        JointAdjustmentProgress progress = inner;
        progress.replicate = static_cast<int>(b) + 1;
        progress.num_replicates = static_cast<int>(num_blocks);
        progress.seconds = std::chrono::duration<double>(
                               std::chrono::steady_clock::now() - start)
                               .count();
        options.progress(progress);
      };
    }
    const JointAdjustmentResult replicate = AdjustJointly(
        WithoutBlock(problem, *result, image_order, begin, end), resolve);
    if (!replicate.IsSuccess()) {
      if (first_failure.empty()) {
        first_failure =
            std::string(ToString(replicate.status)) + ": " + replicate.message;
      }
      continue;
    }
    deviations.push_back(MountDeviations(*result, replicate));
  }
  out.time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  out.num_blocks = static_cast<int>(deviations.size());
  if (deviations.size() < 3) {
    out.reason = std::to_string(deviations.size()) + " of " +
                 std::to_string(num_blocks) +
                 " re-solves succeeded: fewer than 3 (" + first_failure + ")";
    return out;
  }
  const double g = static_cast<double>(deviations.size());
  const Eigen::Index n = deviations.front().size();
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(n);
  for (const Eigen::VectorXd& deviation : deviations) mean += deviation / g;
  out.mounts_covariance = Eigen::MatrixXd::Zero(n, n);
  for (const Eigen::VectorXd& deviation : deviations) {
    out.mounts_covariance +=
        (deviation - mean) * (deviation - mean).transpose();
  }
  out.mounts_covariance *= (g - 1.0) / g;
  out.covariance = out.mounts_covariance.topLeftCorner<5, 5>();
  out.ran = true;

  // The model's covariance: the stated one without its widening (a result
  // of one mount may hold only the 5 x 5 block).
  if (result->mounts_covariance.rows() != n) {
    result->mounts_covariance = result->covariance;
    result->mounts_covariance_widening = result->covariance_widening;
  }
  const Eigen::VectorXd widening = result->mounts_covariance_widening;
  const Eigen::MatrixXd model = widening.cwiseInverse().asDiagonal() *
                                result->mounts_covariance *
                                widening.cwiseInverse().asDiagonal();
  out.mounts_ratio.resize(n);
  Eigen::VectorXd wider = widening;
  for (Eigen::Index k = 0; k < n; ++k) {
    out.mounts_ratio[k] = std::sqrt(out.mounts_covariance(k, k) / model(k, k));
    wider[k] = std::max(wider[k], out.mounts_ratio[k]);
  }
  out.ratio = out.mounts_ratio.head<5>();
  result->mounts_covariance_widening = wider;
  result->mounts_covariance = wider.asDiagonal() * model * wider.asDiagonal();
  if (n > 5) {
    // On a rig the widening per standard deviation keeps the model's
    // correlations between cameras, so a camera-to-camera difference could
    // stay narrower than the jackknife's spread of it. Adding the positive
    // part of (jackknife - stated) makes the stated covariance at least the
    // jackknife's in every direction: a^T (C + (V - C)_+) a >= a^T V a.
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> excess(
        out.mounts_covariance - result->mounts_covariance);
    const Eigen::VectorXd positive = excess.eigenvalues().cwiseMax(0.0);
    result->mounts_covariance += excess.eigenvectors() * positive.asDiagonal() *
                                 excess.eigenvectors().transpose();
    for (Eigen::Index k = 0; k < n; ++k) {
      result->mounts_covariance_widening[k] =
          std::sqrt(result->mounts_covariance(k, k) / model(k, k));
    }
  }
  result->covariance_widening = result->mounts_covariance_widening.head<5>();
  result->covariance = result->mounts_covariance.topLeftCorner<5, 5>();
  return out;
}

}  // namespace odomcal
