// The joint adjustment's residuals that are not templates
// (joint_adjustment_cost.h).
#include "odomcal/solver/joint_adjustment_cost.h"

#include <Eigen/Cholesky>
#include <ceres/autodiff_cost_function.h>

namespace odomcal::internal {
namespace {

template <ProjectionModel kModel>
ceres::CostFunction* CreateReprojectionCost(const Eigen::Vector2d& pixel,
                                            double pixel_sigma) {
  return new ceres::AutoDiffCostFunction<ReprojectionCost<kModel>,
                                         2,
                                         3,
                                         4,
                                         2,
                                         1,
                                         3,
                                         ProjectionNumParams(kModel)>(
      new ReprojectionCost<kModel>(pixel, pixel_sigma));
}

}  // namespace

ceres::CostFunction* ReprojectionCostFor(ProjectionModel model,
                                         const Eigen::Vector2d& pixel,
                                         double pixel_sigma) {
  return VisitProjectionModel(model, [&](auto constant) {
    return CreateReprojectionCost<decltype(constant)::value>(pixel,
                                                             pixel_sigma);
  });
}

bool ReprojectionResidualFor(ProjectionModel model,
                             const Eigen::Vector2d& pixel,
                             const double* const* parameters,
                             double* residual) {
  return VisitProjectionModel(model, [&](auto constant) {
    return ReprojectionCost<decltype(constant)::value>(pixel, 1.0)(
        parameters[0],
        parameters[1],
        parameters[2],
        parameters[3],
        parameters[4],
        parameters[5],
        residual);
  });
}

bool SqrtInformation(const Eigen::Matrix3d& covariance, Eigen::Matrix3d* w) {
  const Eigen::LLT<Eigen::Matrix3d> llt(covariance);
  if (llt.info() != Eigen::Success || !covariance.allFinite()) return false;
  // covariance = L L^T, so covariance^-1 = L^-T L^-1 and W = L^-1.
  *w = llt.matrixL().solve(Eigen::Matrix3d::Identity());
  return true;
}

}  // namespace odomcal::internal
