#include "odomcal/solver/camera_intrinsics_manifold.h"

#include <cmath>
#include <cstddef>

namespace odomcal::internal {

CameraIntrinsicsManifold::CameraIntrinsicsManifold(ProjectionModel model)
    : num_params_(ProjectionNumParams(model)) {
  const int cx = PrincipalPointIndex(model);
  for (int k = 0; k < cx; ++k) focal_.push_back(k);
  for (int k = cx + 2; k < num_params_; ++k) distortion_.push_back(k);
}

int CameraIntrinsicsManifold::AmbientSize() const { return num_params_; }

int CameraIntrinsicsManifold::TangentSize() const {
  return 1 + static_cast<int>(distortion_.size());
}

bool CameraIntrinsicsManifold::Plus(const double* x,
                                    const double* delta,
                                    double* x_plus_delta) const {
  for (int k = 0; k < num_params_; ++k) x_plus_delta[k] = x[k];
  // Linear in delta (not exp): Ceres' convergence test takes Plus(x,
  // -gradient), whatever the gradient's size.
  for (const int k : focal_) x_plus_delta[k] = x[k] * (1.0 + delta[0]);
  for (size_t j = 0; j < distortion_.size(); ++j) {
    x_plus_delta[distortion_[j]] = x[distortion_[j]] + delta[1 + j];
  }
  return true;
}

bool CameraIntrinsicsManifold::PlusJacobian(const double* x,
                                            double* jacobian) const {
  // Row-major, ambient x tangent, at delta = 0.
  const std::ptrdiff_t tangent = TangentSize();
  for (std::ptrdiff_t k = 0; k < num_params_ * tangent; ++k) jacobian[k] = 0.0;
  for (const int k : focal_) jacobian[k * tangent] = x[k];
  for (size_t j = 0; j < distortion_.size(); ++j) {
    jacobian[distortion_[j] * tangent + 1 + static_cast<std::ptrdiff_t>(j)] =
        1.0;
  }
  return true;
}

bool CameraIntrinsicsManifold::Minus(const double* y,
                                     const double* x,
                                     double* y_minus_x) const {
  const int f = focal_.front();
  if (!(x[f] > 0.0) || !(y[f] > 0.0)) return false;
  y_minus_x[0] = y[f] / x[f] - 1.0;
  for (size_t j = 0; j < distortion_.size(); ++j) {
    y_minus_x[1 + j] = y[distortion_[j]] - x[distortion_[j]];
  }
  return true;
}

bool CameraIntrinsicsManifold::MinusJacobian(const double* x,
                                             double* jacobian) const {
  // Row-major, tangent x ambient, at y = x.
  for (int k = 0; k < TangentSize() * num_params_; ++k) jacobian[k] = 0.0;
  const int f = focal_.front();
  if (!(x[f] > 0.0)) return false;
  jacobian[f] = 1.0 / x[f];
  for (size_t j = 0; j < distortion_.size(); ++j) {
    jacobian[(1 + j) * num_params_ + distortion_[j]] = 1.0;
  }
  return true;
}

}  // namespace odomcal::internal
