#include "odomcal/adapters/camera_pose_drift.h"

#include <Eigen/Eigenvalues>

#include <stdexcept>
#include <string>

namespace odomcal {
namespace {

// Above this share of the long-span rotation's mean square across the
// plane (an error of about a fifth of the rotation) the motion is not planar.
constexpr double kMaxOffPlaneShare = 0.05;
// Mean squares across the plane below this (radians squared, or relative to
// the mean squared step) are rounding, not error.
constexpr double kRoundingSquare = 1e-20;

// Rotation vector and translation of cam_k_from_cam_{k+m}, in camera k.
struct Increment {
  Eigen::Vector3d rotation;
  Eigen::Vector3d translation;
};

std::vector<Increment> Increments(const std::vector<Trajectory>& segments,
                                  int span) {
  std::vector<Increment> increments;
  for (const Trajectory& segment : segments) {
    const std::vector<StampedPose>& poses = segment.poses;
    for (size_t k = 0; k + span < poses.size(); ++k) {
      const Rigid3d motion = Inverse(poses[k].world_from_sensor) *
                             poses[k + span].world_from_sensor;
      increments.push_back({LogRotation(motion.rotation), motion.translation});
    }
  }
  return increments;
}

// Mean squares across the plane whose normal is `axis`: rotation components
// across it, translation component along it.
std::pair<double, double> MeanSquaresAcross(
    const std::vector<Increment>& increments, const Eigen::Vector3d& axis) {
  double rotation = 0.0;
  double translation = 0.0;
  for (const Increment& increment : increments) {
    const double along = increment.rotation.dot(axis);
    rotation += increment.rotation.squaredNorm() - along * along;
    const double out = increment.translation.dot(axis);
    translation += out * out;
  }
  const double n = static_cast<double>(increments.size());
  return {rotation / n, translation / n};
}

}  // namespace

void CameraPoseDriftOptions::Check() const {
  if (span < 2) {
    throw std::invalid_argument("span must be >= 2, got " +
                                std::to_string(span));
  }
  if (min_num_pairs < 1) {
    throw std::invalid_argument("min_num_pairs must be >= 1, got " +
                                std::to_string(min_num_pairs));
  }
}

CameraPoseDriftTest TestCameraPoseDrift(
    const std::vector<Trajectory>& camera_segments,
    const CameraPoseDriftOptions& options) {
  options.Check();
  CameraPoseDriftTest test;
  test.span = options.span;
  test.threshold = 0.5 * (options.span + 1);
  const std::vector<Increment> short_span = Increments(camera_segments, 1);
  const std::vector<Increment> long_span =
      Increments(camera_segments, options.span);
  test.num_pairs = static_cast<int>(long_span.size());
  if (test.num_pairs < options.min_num_pairs) return test;

  // The common axis of the rotation increments: the principal direction of
  // their rotation vectors (sign-free), from the long span (more rotation).
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Increment& increment : long_span) {
    scatter += increment.rotation * increment.rotation.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  if (!(eigen.eigenvalues()(2) > 0.0)) return test;  // no rotation at all
  const Eigen::Vector3d axis = eigen.eigenvectors().col(2);

  const auto [rotation_short, translation_short] =
      MeanSquaresAcross(short_span, axis);
  const auto [rotation_long, translation_long] =
      MeanSquaresAcross(long_span, axis);
  // Motion that leaves the plane for real (not a ground robot) would read
  // as drift: the test then stays undecided.
  const double rotation_long_total = scatter.trace() / test.num_pairs;
  if (!(rotation_long <= kMaxOffPlaneShare * rotation_long_total)) return test;
  // Exact poses have nothing across the plane but rounding.
  double step_square = 0.0;
  for (const Increment& increment : short_span) {
    step_square += increment.translation.squaredNorm();
  }
  step_square /= static_cast<double>(short_span.size());
  if (!(rotation_short > kRoundingSquare) ||
      !(translation_short > kRoundingSquare * step_square)) {
    return test;
  }
  test.rotation_ratio = rotation_long / rotation_short;
  test.translation_ratio = translation_long / translation_short;
  test.decided = true;
  test.drifting = test.rotation_ratio >= test.threshold &&
                  test.translation_ratio >= test.threshold;
  return test;
}

}  // namespace odomcal
