#include "odomcal/datasets/rendering/camera_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace odomcal {

void CameraIntrinsics::Check() const {
  if (width <= 0 || height <= 0) {
    throw std::invalid_argument(
        "CameraIntrinsics: width and height must be > 0");
  }
  if (!(fx > 0.0) || !(fy > 0.0)) {
    throw std::invalid_argument("CameraIntrinsics: fx and fy must be > 0");
  }
  if (!std::isfinite(cx) || !std::isfinite(cy) || !std::isfinite(k1)) {
    throw std::invalid_argument("CameraIntrinsics: cx, cy, k1 must be finite");
  }
  if (k1 != 0.0) {
    if (fx != fy) {
      throw std::invalid_argument(
          "CameraIntrinsics: SIMPLE_RADIAL (k1 != 0) needs fx == fy");
    }
    // Distorted radius r (1 + k1 r^2) must grow with r out to the corners,
    // i.e. 1 + 3 k1 r^2 > 0 (checked with margin on the undistorted radius,
    // approximated by the distorted one, which is larger for k1 < 0).
    const double corner_x = std::max(cx, width - cx) / fx;
    const double corner_y = std::max(cy, height - cy) / fy;
    const double r2 = corner_x * corner_x + corner_y * corner_y;
    if (1.0 + 3.0 * k1 * r2 < 0.2) {
      throw std::invalid_argument(
          "CameraIntrinsics.k1: distortion not monotonic inside the image");
    }
  }
}

std::string CameraIntrinsics::ColmapModelName() const {
  return k1 == 0.0 ? "PINHOLE" : "SIMPLE_RADIAL";
}

std::vector<double> CameraIntrinsics::ColmapParams() const {
  if (k1 == 0.0) return {fx, fy, cx, cy};
  return {fx, cx, cy, k1};
}

std::vector<std::string> CameraIntrinsics::ColmapParamNames() const {
  if (k1 == 0.0) return {"fx", "fy", "cx", "cy"};
  return {"f", "cx", "cy", "k"};
}

Eigen::Vector2d CameraIntrinsics::Project(
    const Eigen::Vector3d& p_in_cam) const {
  const double x = p_in_cam.x() / p_in_cam.z();
  const double y = p_in_cam.y() / p_in_cam.z();
  const double d = 1.0 + k1 * (x * x + y * y);
  return Eigen::Vector2d(fx * d * x + cx, fy * d * y + cy);
}

Eigen::Vector3d CameraIntrinsics::PixelToRay(
    const Eigen::Vector2d& pixel) const {
  const double xd = (pixel.x() - cx) / fx;
  const double yd = (pixel.y() - cy) / fy;
  if (k1 == 0.0) return Eigen::Vector3d(xd, yd, 1.0);
  // Solve r (1 + k1 r^2) = rd for the undistorted radius r.
  const double rd = std::hypot(xd, yd);
  if (rd == 0.0) return Eigen::Vector3d(0.0, 0.0, 1.0);
  double r = rd;
  for (int i = 0; i < 20; ++i) {
    const double f = r * (1.0 + k1 * r * r) - rd;
    const double step = f / (1.0 + 3.0 * k1 * r * r);
    r -= step;
    if (std::abs(step) < 1e-12) break;
  }
  const double s = r / rd;
  return Eigen::Vector3d(xd * s, yd * s, 1.0);
}

}  // namespace odomcal
