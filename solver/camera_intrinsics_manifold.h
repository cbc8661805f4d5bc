// The camera intrinsics a bundle adjustment of planar motion can refine
// (internal: Ceres types stay out of the public headers).
//
// One scale on the focal length(s) and the distortion coefficients; the
// principal point held, as COLMAP's bundle adjustment holds it by default
// (under planar motion it trades against the camera's pitch and yaw). A
// model with fx and fy keeps their ratio: motion in a plane does not fix the
// focal length along the plane's normal apart from the one across it (a
// level camera's fy is free: COLMAP's own bundle adjustment of a planar drive
// can end with fy several times fx), so only their common scale is
// refined.
//
// Tangent: [relative change of the focal length(s), distortion coefficients
// in the model's order (camera_projection.h)].
#pragma once

#include "odomcal/solver/camera_projection.h"

#include <ceres/manifold.h>

#include <vector>

namespace odomcal::internal {

class CameraIntrinsicsManifold : public ceres::Manifold {
 public:
  explicit CameraIntrinsicsManifold(ProjectionModel model);

  int AmbientSize() const override;
  int TangentSize() const override;
  bool Plus(const double* x,
            const double* delta,
            double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y,
             const double* x,
             double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;

 private:
  int num_params_ = 0;
  std::vector<int> focal_;       // indices of f, or fx and fy
  std::vector<int> distortion_;  // indices after the principal point
};

}  // namespace odomcal::internal
