// Renders what a camera sees in a RoomScene by ray casting.
//
// Pixel (i, j) is the mean of S x S rays through the sub-pixel positions
// (i + (a + 0.5) / S, j + (b + 0.5) / S), a, b = 0 .. S-1, in COLMAP's
// continuous pixel coordinates (camera_model.h), so a surface point p lands,
// on average, exactly at Project(cam_from_room * p). Each ray takes the
// nearest surface (both faces of a rectangle are visible) and a trilinear
// mip-mapped texture lookup whose level follows the ray's footprint on the
// surface (depth / focal / S, stretched by 1 / cos(incidence), at most
// `max_footprint_stretch`): enough anti-aliasing that SIFT sees stable
// features. Rays that hit nothing get `background_rgb`. No lighting: the
// texture colour is the pixel colour. Rows are shared among `num_threads`
// std::threads; the output does not depend on the thread count.
#pragma once

#include "odomcal/datasets/rendering/camera_model.h"
#include "odomcal/datasets/rendering/room_scene.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace odomcal {

// 8-bit RGB, row-major, row 0 at the top: rgb[(y * width + x) * 3 + c].
struct Image {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgb;
};

struct RenderOptions {
  int supersampling = 2;  // S: S x S rays per pixel
  int num_threads = 2;
  // Caps the isotropic blur at grazing angles. Measured with COLMAP 3.8 on
  // `small`: 4 blurred the floor (its near, high-parallax features) and one
  // of two runs built a wrong model (4 deg); 1.5 keeps the floor sharp.
  double max_footprint_stretch = 1.5;
  Eigen::Vector3f background_rgb = Eigen::Vector3f::Zero();
  void Check() const;  // throws std::invalid_argument naming the field
};

// room_from_cam: the camera pose in the scene's frame (x_in_room =
// room_from_cam * x_in_cam). Throws std::invalid_argument for invalid
// intrinsics or options.
Image RenderImage(const RoomScene& scene,
                  const CameraIntrinsics& camera,
                  const Rigid3d& room_from_cam,
                  const RenderOptions& options);

}  // namespace odomcal
