// Surfaces are collected first with a texture request each (size in texels,
// seed, or flat); the textures are then generated on `num_threads` threads,
// each request independent, so the result does not depend on the thread count.

#include "odomcal/datasets/rendering/room_scene.h"

#include "odomcal/datasets/rendering/value_noise.h"
#include "odomcal/datasets/simulation/seed.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <thread>

namespace odomcal {
namespace {

struct TextureRequest {
  bool textured = true;
  int width = 1, height = 1;
  uint64_t seed = 0;
};

class SceneBuilder {
 public:
  explicit SceneBuilder(const RoomSceneOptions& options) : options_(options) {}

  void Add(const Eigen::Vector3d& origin,
           const Eigen::Vector3d& u,
           const Eigen::Vector3d& v,
           double u_extent,
           double v_extent,
           bool textured) {
    Surface s;
    s.origin = origin;
    s.u_axis = u.normalized();
    s.v_axis = v.normalized();
    s.u_extent_m = u_extent;
    s.v_extent_m = v_extent;
    s.texel_size_m = options_.texel_size_m;
    s.texture_index = static_cast<int>(requests_.size());
    TextureRequest request;
    request.textured = textured;
    request.width =
        std::max(1, static_cast<int>(std::ceil(u_extent / s.texel_size_m)));
    request.height =
        std::max(1, static_cast<int>(std::ceil(v_extent / s.texel_size_m)));
    request.seed = DeriveSeed(options_.seed, requests_.size());
    requests_.push_back(request);
    scene_.surfaces.push_back(s);
  }

  RoomScene Finish() {
    std::vector<std::optional<Texture>> textures(requests_.size());
    const auto work = [&](int thread) {
      for (size_t i = thread; i < requests_.size(); i += options_.num_threads) {
        const TextureRequest& r = requests_[i];
        if (!r.textured) {
          textures[i] = Texture::Constant(options_.featureless_rgb);
          continue;
        }
        ValueNoiseOptions noise;
        noise.width = r.width;
        noise.height = r.height;
        noise.seed = r.seed;
        noise.min_period_texels = options_.min_period_texels;
        noise.max_period_texels = options_.max_period_texels;
        if (options_.repeat_period_texels > 0) {
          textures[i] = RepeatedTile(r.width, r.height);
          continue;
        }
        textures[i] = MakeValueNoiseTexture(noise);
      }
    };
    std::vector<std::thread> threads;
    for (int t = 1; t < options_.num_threads; ++t)
      threads.emplace_back(work, t);
    work(0);
    for (std::thread& thread : threads) thread.join();
    for (std::optional<Texture>& texture : textures) {
      scene_.textures.push_back(std::move(*texture));
    }
    return std::move(scene_);
  }

 private:
  // One tile of noise (the same seed for every surface) repeated over
  // width x height texels.
  Texture RepeatedTile(int width, int height) const {
    const int period = options_.repeat_period_texels;
    ValueNoiseOptions noise;
    noise.width = period;
    noise.height = period;
    noise.seed = options_.seed;
    noise.min_period_texels = options_.min_period_texels;
    noise.max_period_texels = std::min(options_.max_period_texels, period);
    const Texture tile = MakeValueNoiseTexture(noise);
    std::vector<float> rgb(static_cast<size_t>(width) * height * 3);
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const Eigen::Vector3f texel = tile.Texel(0, x % period, y % period);
        for (int c = 0; c < 3; ++c) {
          rgb[(static_cast<size_t>(y) * width + x) * 3 + c] = texel[c];
        }
      }
    }
    return Texture(width, height, std::move(rgb));
  }

  RoomSceneOptions options_;
  std::vector<TextureRequest> requests_;
  RoomScene scene_;
};

}  // namespace

void RoomSceneOptions::Check() const {
  if (!(texel_size_m > 0.0)) {
    throw std::invalid_argument("RoomSceneOptions.texel_size_m must be > 0");
  }
  if (num_threads < 1) {
    throw std::invalid_argument("RoomSceneOptions.num_threads must be >= 1");
  }
  ValueNoiseOptions noise;
  noise.min_period_texels = min_period_texels;
  noise.max_period_texels = max_period_texels;
  noise.Check();
  const int repeat = repeat_period_texels;
  if (repeat < 0 || (repeat > 0 && ((repeat & (repeat - 1)) != 0 ||
                                    repeat < min_period_texels))) {
    throw std::invalid_argument(
        "RoomSceneOptions.repeat_period_texels must be 0 or a power of two "
        ">= min_period_texels");
  }
}

RoomScene BuildRoomScene(const RoomLayout& layout,
                         const RoomSceneOptions& options) {
  layout.Check();
  options.Check();
  SceneBuilder builder(options);
  const Eigen::Vector3d ex = Eigen::Vector3d::UnitX(),
                        ey = Eigen::Vector3d::UnitY(),
                        ez = Eigen::Vector3d::UnitZ();
  const double slope = std::tan(layout.floor_slope_deg * M_PI / 180.0);
  for (const FloorPatch& floor : layout.floors) {
    const Eigen::Vector2d size = floor.max_xy - floor.min_xy;
    builder.Add(Eigen::Vector3d(
                    floor.min_xy.x(),
                    floor.min_xy.y(),
                    slope * (floor.min_xy.x() - layout.floor_slope_pivot_x_m)),
                Eigen::Vector3d(1.0, 0.0, slope),
                ey,
                size.x() * std::sqrt(1.0 + slope * slope),
                size.y(),
                floor.textured);
    if (layout.ceiling_height_m) {
      builder.Add(
          Eigen::Vector3d(
              floor.min_xy.x(), floor.min_xy.y(), *layout.ceiling_height_m),
          ex,
          ey,
          size.x(),
          size.y(),
          floor.textured);
    }
  }
  for (const WallSpec& wall : layout.walls) {
    const Eigen::Vector2d d = wall.to - wall.from;
    builder.Add(Eigen::Vector3d(wall.from.x(), wall.from.y(), 0.0),
                Eigen::Vector3d(d.x(), d.y(), 0.0),
                ez,
                d.norm(),
                wall.height_m,
                wall.textured);
  }
  for (const BoxSpec& box : layout.boxes) {
    const std::vector<Eigen::Vector2d> c = box.Footprint();
    for (int i = 0; i < 4; ++i) {
      const Eigen::Vector2d d = c[(i + 1) % 4] - c[i];
      builder.Add(Eigen::Vector3d(c[i].x(), c[i].y(), 0.0),
                  Eigen::Vector3d(d.x(), d.y(), 0.0),
                  ez,
                  d.norm(),
                  box.size_m.z(),
                  box.textured);
    }
    const Eigen::Vector2d du = c[1] - c[0], dv = c[3] - c[0];
    builder.Add(Eigen::Vector3d(c[0].x(), c[0].y(), box.size_m.z()),
                Eigen::Vector3d(du.x(), du.y(), 0.0),
                Eigen::Vector3d(dv.x(), dv.y(), 0.0),
                du.norm(),
                dv.norm(),
                box.textured);
  }
  return builder.Finish();
}

Surface MakeRectangle(const Eigen::Vector3d& center,
                      const Eigen::Vector3d& u_axis,
                      const Eigen::Vector3d& v_axis,
                      double width_m,
                      double height_m,
                      int texture_index,
                      double texel_size_m) {
  Surface s;
  s.u_axis = u_axis.normalized();
  s.v_axis = v_axis.normalized();
  s.origin = center - 0.5 * width_m * s.u_axis - 0.5 * height_m * s.v_axis;
  s.u_extent_m = width_m;
  s.v_extent_m = height_m;
  s.texture_index = texture_index;
  s.texel_size_m = texel_size_m;
  return s;
}

}  // namespace odomcal
