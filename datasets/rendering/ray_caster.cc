// For every sub-pixel ray: intersect all rectangles (planes, then the 2D
// extent test), keep the nearest, convert the hit to texel coordinates, pick
// the mip level log2(footprint / texel size) and sample. The footprint is the
// sub-pixel's width at the hit, z_cam / f / S metres across for a surface
// facing the camera, widened by the obliquity (capped). Brute force over the
// rectangles (scenes have a few dozen), after culling those behind the
// camera and testing each ray only against rectangles whose projected
// bounding box contains its pixel.

#include "odomcal/datasets/rendering/ray_caster.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <thread>

namespace odomcal {
namespace {

// Surface in the camera frame with precomputed plane terms.
struct CameraSurface {
  Eigen::Vector3d origin, u_axis, v_axis, normal;
  // The dual basis of (u_axis, v_axis) in their plane: a point q of the plane
  // is a * u_axis + b * v_axis with a = q . u_dual, b = q . v_dual (the axes
  // themselves for a rectangle).
  Eigen::Vector3d u_dual, v_dual;
  double plane_offset;  // normal . origin
  double u_extent, v_extent, inv_texel;
  const Texture* texture;
  // Pixel-space bounding box of the projection (the whole plane of pixels
  // when a corner is behind the camera or the lens distorts).
  double min_u, max_u, min_v, max_v;
};

constexpr double kMinDepth = 1e-6;

}  // namespace

void RenderOptions::Check() const {
  if (supersampling < 1 || supersampling > 16) {
    throw std::invalid_argument(
        "RenderOptions.supersampling must be in [1, 16]");
  }
  if (num_threads < 1) {
    throw std::invalid_argument("RenderOptions.num_threads must be >= 1");
  }
  if (!(max_footprint_stretch >= 1.0)) {
    throw std::invalid_argument(
        "RenderOptions.max_footprint_stretch must be >= 1");
  }
}

Image RenderImage(const RoomScene& scene,
                  const CameraIntrinsics& camera,
                  const Rigid3d& room_from_cam,
                  const RenderOptions& options) {
  camera.Check();
  options.Check();
  // Work in the camera frame: rays start at the origin.
  const Rigid3d cam_from_room = Inverse(room_from_cam);
  const Eigen::Matrix3d rotation = cam_from_room.rotation.toRotationMatrix();
  std::vector<CameraSurface> surfaces;
  surfaces.reserve(scene.surfaces.size());
  for (const Surface& s : scene.surfaces) {
    if (s.texture_index < 0 ||
        s.texture_index >= static_cast<int>(scene.textures.size())) {
      throw std::invalid_argument(
          "RenderImage: surface texture_index out of range");
    }
    CameraSurface c;
    c.origin = cam_from_room * s.origin;
    c.u_axis = rotation * s.u_axis;
    c.v_axis = rotation * s.v_axis;
    c.normal = c.u_axis.cross(c.v_axis);
    const double skew = c.u_axis.dot(c.v_axis);
    c.u_dual = c.u_axis;
    c.v_dual = c.v_axis;
    if (std::abs(skew) > 1e-12) {  // a parallelogram; rectangles stay exact
      c.normal.normalize();
      const double inv = 1.0 / (1.0 - skew * skew);
      c.u_dual = (c.u_axis - skew * c.v_axis) * inv;
      c.v_dual = (c.v_axis - skew * c.u_axis) * inv;
    }
    c.plane_offset = c.normal.dot(c.origin);
    c.u_extent = s.u_extent_m;
    c.v_extent = s.v_extent_m;
    c.inv_texel = 1.0 / s.texel_size_m;
    c.texture = &scene.textures[s.texture_index];
    // Culling: a rectangle projects inside the hull of its corners when all
    // are in front and there is no distortion (straight lines stay straight).
    const double inf = std::numeric_limits<double>::infinity();
    c.min_u = c.min_v = -inf;
    c.max_u = c.max_v = inf;
    bool all_behind = true, all_in_front = true;
    Eigen::Vector2d lo(inf, inf), hi(-inf, -inf);
    for (int corner = 0; corner < 4; ++corner) {
      const Eigen::Vector3d p = c.origin +
                                (corner & 1) * c.u_extent * c.u_axis +
                                (corner >> 1) * c.v_extent * c.v_axis;
      all_behind = all_behind && p.z() <= kMinDepth;
      all_in_front = all_in_front && p.z() > kMinDepth;
      if (p.z() > kMinDepth) {
        const Eigen::Vector2d uv = camera.Project(p);
        lo = lo.cwiseMin(uv);
        hi = hi.cwiseMax(uv);
      }
    }
    if (all_behind) continue;
    if (all_in_front && camera.k1 == 0.0) {
      if (hi.x() < 0.0 || lo.x() > camera.width || hi.y() < 0.0 ||
          lo.y() > camera.height) {
        continue;
      }
      c.min_u = lo.x() - 0.01;
      c.max_u = hi.x() + 0.01;
      c.min_v = lo.y() - 0.01;
      c.max_v = hi.y() + 0.01;
    }
    surfaces.push_back(c);
  }

  const int S = options.supersampling;
  const double focal = std::sqrt(camera.fx * camera.fy);
  // Footprint of one sub-pixel per unit depth, for a fronto-parallel surface.
  const double footprint_per_depth = 1.0 / (focal * S);
  const float weight = 1.0f / static_cast<float>(S * S);

  Image image;
  image.width = camera.width;
  image.height = camera.height;
  image.rgb.assign(static_cast<size_t>(camera.width) * camera.height * 3, 0);

  const auto trace = [&](const Eigen::Vector2d& pixel) -> Eigen::Vector3f {
    const Eigen::Vector3d ray = camera.PixelToRay(pixel);
    double best_t = std::numeric_limits<double>::infinity();
    const CameraSurface* best = nullptr;
    double best_a = 0.0, best_b = 0.0;
    for (const CameraSurface& s : surfaces) {
      if (pixel.x() < s.min_u || pixel.x() > s.max_u || pixel.y() < s.min_v ||
          pixel.y() > s.max_v) {
        continue;
      }
      const double denom = s.normal.dot(ray);
      if (std::abs(denom) < 1e-12) continue;
      const double t = s.plane_offset / denom;
      if (!(t > kMinDepth) || t >= best_t) continue;
      const Eigen::Vector3d q = t * ray - s.origin;
      const double a = q.dot(s.u_dual);
      if (a < 0.0 || a > s.u_extent) continue;
      const double b = q.dot(s.v_dual);
      if (b < 0.0 || b > s.v_extent) continue;
      best_t = t;
      best = &s;
      best_a = a;
      best_b = b;
    }
    if (best == nullptr) return options.background_rgb;
    // ray = (x, y, 1), so t is the depth z_cam of the hit.
    const double cos_incidence = std::abs(best->normal.dot(ray)) / ray.norm();
    const double stretch = std::min(options.max_footprint_stretch,
                                    1.0 / std::max(cos_incidence, 1e-6));
    const double footprint_texels =
        best_t * ray.norm() * footprint_per_depth * stretch * best->inv_texel;
    const double level = std::log2(std::max(footprint_texels, 1e-6));
    return best->texture->Sample(
        best_a * best->inv_texel, best_b * best->inv_texel, level);
  };

  const auto render_rows = [&](int first_row) {
    for (int y = first_row; y < camera.height; y += options.num_threads) {
      for (int x = 0; x < camera.width; ++x) {
        Eigen::Vector3f sum = Eigen::Vector3f::Zero();
        for (int b = 0; b < S; ++b) {
          for (int a = 0; a < S; ++a) {
            sum += trace(Eigen::Vector2d(x + (a + 0.5) / S, y + (b + 0.5) / S));
          }
        }
        uint8_t* out =
            &image.rgb[(static_cast<size_t>(y) * camera.width + x) * 3];
        for (int c = 0; c < 3; ++c) {
          const float v = std::clamp(sum[c] * weight, 0.0f, 1.0f);
          out[c] = static_cast<uint8_t>(std::lround(v * 255.0f));
        }
      }
    }
  };
  std::vector<std::thread> threads;
  for (int t = 1; t < options.num_threads; ++t)
    threads.emplace_back(render_rows, t);
  render_rows(0);
  for (std::thread& thread : threads) thread.join();
  return image;
}

}  // namespace odomcal
