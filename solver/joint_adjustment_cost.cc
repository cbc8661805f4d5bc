// The joint adjustment's residuals that are not templates
// (joint_adjustment_cost.h).
#include "odomcal/solver/joint_adjustment_cost.h"

#include "odomcal/solver/angles.h"

#include <Eigen/Cholesky>
#include <ceres/autodiff_cost_function.h>

#include <cmath>

namespace odomcal::internal {
namespace {

template <ProjectionModel kModel>
ceres::CostFunction* CreateReprojectionCost(bool tilted,
                                            const Eigen::Vector2d& pixel,
                                            double pixel_sigma) {
  constexpr int kNumParams = ProjectionNumParams(kModel);
  if (tilted) {
    return new ceres::AutoDiffCostFunction<TiltedReprojectionCost<kModel>,
                                           2,
                                           3,
                                           3,
                                           4,
                                           2,
                                           1,
                                           3,
                                           kNumParams>(
        new TiltedReprojectionCost<kModel>(pixel, pixel_sigma));
  }
  return new ceres::AutoDiffCostFunction<ReprojectionCost<kModel>,
                                         2,
                                         3,
                                         4,
                                         2,
                                         1,
                                         3,
                                         kNumParams>(
      new ReprojectionCost<kModel>(pixel, pixel_sigma));
}

}  // namespace

ceres::CostFunction* ReprojectionCostFor(ProjectionModel model,
                                         bool tilted,
                                         const Eigen::Vector2d& pixel,
                                         double pixel_sigma) {
  return VisitProjectionModel(model, [&](auto constant) {
    return CreateReprojectionCost<decltype(constant)::value>(
        tilted, pixel, pixel_sigma);
  });
}

bool ReprojectionResidualFor(ProjectionModel model,
                             bool tilted,
                             const Eigen::Vector2d& pixel,
                             const double* const* parameters,
                             double* residual) {
  return VisitProjectionModel(model, [&](auto constant) {
    constexpr ProjectionModel kModel = decltype(constant)::value;
    if (tilted) {
      return TiltedReprojectionCost<kModel>(pixel, 1.0)(parameters[0],
                                                        parameters[1],
                                                        parameters[2],
                                                        parameters[3],
                                                        parameters[4],
                                                        parameters[5],
                                                        parameters[6],
                                                        residual);
    }
    return ReprojectionCost<kModel>(pixel, 1.0)(parameters[0],
                                                parameters[1],
                                                parameters[2],
                                                parameters[3],
                                                parameters[4],
                                                parameters[5],
                                                residual);
  });
}

namespace {

// W = L^-1 of covariance = L L^T, so that W^T W = covariance^-1.
template <int kSize>
bool SqrtInformationOf(const Eigen::Matrix<double, kSize, kSize>& covariance,
                       Eigen::Matrix<double, kSize, kSize>* w) {
  using Matrix = Eigen::Matrix<double, kSize, kSize>;
  const Eigen::LLT<Matrix> llt(covariance);
  if (llt.info() != Eigen::Success || !covariance.allFinite()) return false;
  *w = llt.matrixL().solve(Matrix::Identity());
  return true;
}

}  // namespace

GroundBounds GroundBoundsOf(double tilt_rate_rad_per_m, double length_m) {
  // A link of no length still moves the robot on its suspension: 0.01 deg
  // and 0.1 mm.
  constexpr double kMinTiltSigmaRad = 0.01 * kDegToRad;
  constexpr double kMinHeightSigmaM = 1e-4;
  const double tilt = tilt_rate_rad_per_m * length_m;
  return {std::hypot(tilt, kMinTiltSigmaRad),
          std::hypot(0.5 * tilt * length_m, kMinHeightSigmaM)};
}

bool SqrtInformation(const Eigen::Matrix3d& covariance, Eigen::Matrix3d* w) {
  return SqrtInformationOf<3>(covariance, w);
}

bool SqrtInformation(const Eigen::Matrix<double, 6, 6>& covariance,
                     Eigen::Matrix<double, 6, 6>* w) {
  return SqrtInformationOf<6>(covariance, w);
}

}  // namespace odomcal::internal
