// Covariance, standard deviations and observability from the information
// (covariance_analysis_internal.h).

#include "odomcal/solver/angles.h"
#include "odomcal/solver/covariance_analysis_internal.h"
#include "odomcal/solver/observability.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Dense>

#include <cmath>
#include <optional>
#include <vector>

namespace odomcal::internal {
namespace {

// Eigenvalues of the diagonally normalised information below this fraction of
// the largest span its (numerical) null space.
constexpr double kNullSpaceTolerance = 1e-10;
// A parameter takes part in a null direction when its component is above this.
constexpr double kNullComponentTolerance = 0.1;

// An information matrix normalised to a unit diagonal, D I D with
// D = diag(1 / sqrt(I_kk)) (0 where I_kk <= 0), and its eigen-decomposition:
// the normalisation makes the null-space test independent of the parameters'
// units.
struct NormalisedInformation {
  Eigen::VectorXd inv_sqrt;  // D
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig;

  explicit NormalisedInformation(const Eigen::MatrixXd& information)
      : inv_sqrt(information.rows()) {
    for (int k = 0; k < information.rows(); ++k) {
      const double d = information(k, k);
      inv_sqrt(k) = d > 0.0 ? 1.0 / std::sqrt(d) : 0.0;
    }
    eig.compute(inv_sqrt.asDiagonal() * information * inv_sqrt.asDiagonal());
  }
  // Eigenvalue k is below kNullSpaceTolerance of the largest.
  bool IsNull(int k) const {
    return !(eig.eigenvalues()(k) >
             kNullSpaceTolerance * eig.eigenvalues().maxCoeff());
  }
  // The inverse of the information (for a non-singular one).
  Eigen::MatrixXd Inverse() const {
    return inv_sqrt.asDiagonal() * eig.eigenvectors() *
           eig.eigenvalues().cwiseInverse().asDiagonal() *
           eig.eigenvectors().transpose() * inv_sqrt.asDiagonal();
  }
};

}  // namespace

std::optional<Eigen::MatrixXd> InvertInformation(
    const Eigen::MatrixXd& information) {
  if (information.size() == 0 || !information.allFinite() ||
      !(information.diagonal().array() > 0.0).all()) {
    return std::nullopt;
  }
  const NormalisedInformation normalised(information);
  for (int k = 0; k < information.rows(); ++k) {
    if (normalised.IsNull(k)) return std::nullopt;
  }
  return normalised.Inverse();
}

void AnalyseInformation(const Eigen::MatrixXd& information,
                        const std::vector<int>& segments,
                        int num_segments,
                        const CalibrationOptions& options,
                        CalibrationResult* result) {
  Observability& observability = result->observability;
  // The quantity each parameter of the information belongs to.
  std::vector<Determination*> quantities = {&observability.rotation,
                                            &observability.rotation,
                                            &observability.rotation,
                                            &observability.translation_x,
                                            &observability.translation_y};
  for (const int segment : segments) {
    quantities.push_back(&observability.metric_scales[segment]);
  }
  const bool z_estimated =
      observability.translation_z == Determination::kEstimated;
  // z under its prior is no estimate of the data's: its row neither makes
  // it undetermined nor estimated (the prior makes it regular).
  Determination z_under_prior = Determination::kHeld;
  const bool z_row = z_estimated || result->translation_z_prior.moved_by_data;
  if (z_row) {
    quantities.push_back(z_estimated ? &observability.translation_z
                                     : &z_under_prior);
  }
  auto undetermined = [](Determination* quantity) {
    *quantity = Determination::kUndetermined;
  };
  const int n = static_cast<int>(information.rows());
  const Eigen::VectorXd diag = information.diagonal();
  if (n == 0 || !information.allFinite()) {
    undetermined(&observability.rotation);
    return;
  }
  for (int k = 0; k < n; ++k) {
    if (!(diag(k) > 0.0)) undetermined(quantities[k]);
  }
  const NormalisedInformation normalised(information);
  bool singular = false;
  for (int k = 0; k < n; ++k) {
    if (!normalised.IsNull(k)) continue;
    singular = true;
    for (int j = 0; j < n; ++j) {
      if (std::abs(normalised.eig.eigenvectors()(j, k)) >
          kNullComponentTolerance) {
        undetermined(quantities[j]);
      }
    }
  }
  if (singular) {
    return;
  }
  const Eigen::MatrixXd covariance = normalised.Inverse();
  result->covariance = covariance;
  result->covariance_segments = segments;
  const Eigen::Matrix3d rotation_covariance = covariance.topLeftCorner<3, 3>();
  result->stddev_rotation_axes_deg =
      rotation_covariance.diagonal().cwiseSqrt() * kRadToDeg;
  const Eigen::Matrix3d rpy_jacobian =
      RollPitchYawJacobian(result->odom_from_cam.rotation);
  result->stddev_roll_pitch_yaw_deg =
      (rpy_jacobian * rotation_covariance * rpy_jacobian.transpose())
          .diagonal()
          .cwiseSqrt() *
      kRadToDeg;
  result->stddev_translation_xy_m =
      covariance.block<2, 2>(3, 3).diagonal().cwiseSqrt();
  result->stddev_metric_scales_rel.assign(num_segments, 0.0);
  for (size_t k = 0; k < segments.size(); ++k) {
    const double scale = result->metric_scales[segments[k]];
    result->stddev_metric_scales_rel[segments[k]] =
        std::sqrt(covariance(5 + k, 5 + k)) / scale;
  }
  if (z_row) {
    result->stddev_translation_z_m = std::sqrt(covariance(n - 1, n - 1));
    if (z_estimated &&
        result->stddev_translation_z_m > options.max_translation_stddev_m) {
      undetermined(&observability.translation_z);
    }
  }

  if (result->stddev_rotation_axes_deg.maxCoeff() >
      options.max_rotation_stddev_deg) {
    undetermined(&observability.rotation);
  }
  if (result->stddev_translation_xy_m.x() > options.max_translation_stddev_m) {
    undetermined(&observability.translation_x);
  }
  if (result->stddev_translation_xy_m.y() > options.max_translation_stddev_m) {
    undetermined(&observability.translation_y);
  }
  for (const int segment : segments) {
    if (result->stddev_metric_scales_rel[segment] >
        options.max_scale_stddev_rel) {
      undetermined(&observability.metric_scales[segment]);
    }
  }
}

}  // namespace odomcal::internal
