// Textured planar surfaces built from a RoomLayout: the renderer's scene.
//
// Every floor patch, ceiling patch, wall and box face (4 sides + top) is one
// rectangle with its own value-noise texture (its own seed, so nothing in the
// scene repeats), or a flat colour when the layout marks it featureless.
// A point on a surface is origin + a * u_axis + b * v_axis with a in
// [0, u_extent_m], b in [0, v_extent_m]; its texel coordinates are
// (a, b) / texel_size_m. The axes are orthogonal for a rectangle; a
// parallelogram (a tile of sloped ground, road_scene.h) has them at an angle.
// Deterministic for (layout, options).
#pragma once

#include "odomcal/datasets/rendering/room_layout.h"
#include "odomcal/datasets/rendering/texture.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace odomcal {

struct Surface {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();   // a corner, room frame
  Eigen::Vector3d u_axis = Eigen::Vector3d::UnitX();  // unit
  Eigen::Vector3d v_axis = Eigen::Vector3d::UnitY();  // unit, not parallel to u
  double u_extent_m = 1.0;
  double v_extent_m = 1.0;
  int texture_index = 0;
  double texel_size_m = 0.01;  // metres per level-0 texel
};

struct RoomSceneOptions {
  uint64_t seed = 0;
  double texel_size_m = 0.006;  // octaves from 2 to 256 texels: 1.2 cm to 1.5 m
  int min_period_texels = 2;
  int max_period_texels = 256;
  Eigen::Vector3f featureless_rgb = Eigen::Vector3f(0.55f, 0.55f, 0.55f);
  // A repetitive scene: when > 0 (a power of two >= min_period_texels),
  // every textured surface shows one tile of this many texels square,
  // repeated (octaves up to the tile's size); 0: each surface its own
  // noise.
  int repeat_period_texels = 0;
  int num_threads = 2;  // texture generation
  void Check() const;   // throws std::invalid_argument naming the field
};

struct RoomScene {
  std::vector<Surface> surfaces;
  std::vector<Texture> textures;
};

RoomScene BuildRoomScene(const RoomLayout& layout,
                         const RoomSceneOptions& options);

// One surface of a single texture, e.g. for tests: a centred w x h rectangle
// at `center` spanned by the unit axes u, v.
Surface MakeRectangle(const Eigen::Vector3d& center,
                      const Eigen::Vector3d& u_axis,
                      const Eigen::Vector3d& v_axis,
                      double width_m,
                      double height_m,
                      int texture_index,
                      double texel_size_m);

}  // namespace odomcal
