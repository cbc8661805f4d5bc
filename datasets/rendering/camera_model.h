// Pinhole camera with optional one-coefficient radial distortion, in COLMAP's
// conventions: PINHOLE (fx, fy, cx, cy) when k1 == 0, else SIMPLE_RADIAL
// (f, cx, cy, k1) with fx == fy == f.
//
// Projection of p_in_cam (z > 0, camera x right, y down, z forward):
//   (x, y) = (p.x / p.z, p.y / p.z),  d = 1 + k1 (x^2 + y^2),
//   u = fx * d * x + cx,  v = fy * d * y + cy.
// Pixel coordinates are continuous with the centre of pixel (i, j) at
// (i + 0.5, j + 0.5): integer pixel (i, j) covers [i, i+1) x [j, j+1).
// An ideal centred camera therefore has cx = width / 2, cy = height / 2.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

namespace odomcal {

struct CameraIntrinsics {
  int width = 320;
  int height = 240;
  double fx = 260.0, fy = 260.0;
  double cx = 160.0, cy = 120.0;
  double k1 = 0.0;  // SIMPLE_RADIAL when non-zero (then fx must equal fy)

  // Throws std::invalid_argument naming the field: non-positive size or
  // focal length, fx != fy with k1 != 0, or a k1 for which the distortion is
  // not monotonic inside the image (|k1| r^2 too large at the corners).
  void Check() const;

  std::string ColmapModelName() const;       // "PINHOLE" or "SIMPLE_RADIAL"
  std::vector<double> ColmapParams() const;  // in COLMAP's order
  std::vector<std::string> ColmapParamNames() const;

  // Pixel of a point in front of the camera (see above).
  Eigen::Vector2d Project(const Eigen::Vector3d& p_in_cam) const;

  // Direction (x, y, 1) in the camera frame whose projection is `pixel`;
  // inverts the distortion by Newton's method to 1e-12.
  Eigen::Vector3d PixelToRay(const Eigen::Vector2d& pixel) const;
};

}  // namespace odomcal
