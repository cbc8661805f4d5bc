// A mip-mapped RGB texture with bilinear/trilinear lookup.
//
// Texel (i, j) of level 0 covers [i, i+1) x [j, j+1) in texel coordinates, so
// its centre is at (i + 0.5, j + 0.5): the same convention as COLMAP's pixels.
// Level k has ceil(width / 2^k) x ceil(height / 2^k) texels, each the mean of
// the (up to) 2x2 texels below it; coordinates passed to Sample() are always
// level-0 texel coordinates. Addressing clamps to the edge (no wrap-around, so
// nothing repeats). Colours are linear floats in [0, 1].
#pragma once

#include <Eigen/Core>

#include <vector>

namespace odomcal {

class Texture {
 public:
  // `rgb` holds width * height * 3 floats, row-major, row 0 first.
  // Throws std::invalid_argument on non-positive sizes or a size mismatch.
  Texture(int width, int height, std::vector<float> rgb);

  // A 1x1 texture of one colour: a featureless surface.
  static Texture Constant(const Eigen::Vector3f& rgb);

  int width() const { return levels_[0].width; }
  int height() const { return levels_[0].height; }
  int num_levels() const { return static_cast<int>(levels_.size()); }

  // Colour at level-0 texel coordinates (u, v) for a footprint of 2^level
  // texels: trilinear between the two nearest levels (bilinear inside each).
  // level <= 0 samples level 0; levels beyond the last use the last.
  Eigen::Vector3f Sample(double u, double v, double level) const;

  // Bilinear lookup in one level (level-0 coordinates). 0 <= level <
  // num_levels().
  Eigen::Vector3f SampleLevel(double u, double v, int level) const;

  // Raw texel of a level (for tests).
  Eigen::Vector3f Texel(int level, int x, int y) const;

 private:
  struct Level {
    int width = 0, height = 0;
    std::vector<float> rgb;
  };
  std::vector<Level> levels_;
};

}  // namespace odomcal
