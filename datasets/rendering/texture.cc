// Mip levels are built once by 2x2 box averaging (an odd last row/column is
// averaged with itself, i.e. clamped); lookups clamp to the edge.

#include "odomcal/datasets/rendering/texture.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace odomcal {

Texture::Texture(int width, int height, std::vector<float> rgb) {
  if (width <= 0 || height <= 0) {
    throw std::invalid_argument("Texture: size must be positive, got " +
                                std::to_string(width) + "x" +
                                std::to_string(height));
  }
  if (rgb.size() != static_cast<size_t>(width) * height * 3) {
    throw std::invalid_argument("Texture: expected width * height * 3 floats");
  }
  levels_.push_back({width, height, std::move(rgb)});
  while (levels_.back().width > 1 || levels_.back().height > 1) {
    const Level& fine = levels_.back();
    Level coarse;
    coarse.width = (fine.width + 1) / 2;
    coarse.height = (fine.height + 1) / 2;
    coarse.rgb.resize(static_cast<size_t>(coarse.width) * coarse.height * 3);
    for (int y = 0; y < coarse.height; ++y) {
      const int y0 = 2 * y, y1 = std::min(2 * y + 1, fine.height - 1);
      for (int x = 0; x < coarse.width; ++x) {
        const int x0 = 2 * x, x1 = std::min(2 * x + 1, fine.width - 1);
        for (int c = 0; c < 3; ++c) {
          const auto at = [&](int xx, int yy) {
            return fine
                .rgb[(static_cast<size_t>(yy) * fine.width + xx) * 3 + c];
          };
          coarse.rgb[(static_cast<size_t>(y) * coarse.width + x) * 3 + c] =
              0.25f * (at(x0, y0) + at(x1, y0) + at(x0, y1) + at(x1, y1));
        }
      }
    }
    levels_.push_back(std::move(coarse));
  }
}

Texture Texture::Constant(const Eigen::Vector3f& rgb) {
  return Texture(1, 1, {rgb.x(), rgb.y(), rgb.z()});
}

Eigen::Vector3f Texture::Texel(int level, int x, int y) const {
  const Level& l = levels_.at(level);
  x = std::clamp(x, 0, l.width - 1);
  y = std::clamp(y, 0, l.height - 1);
  const float* p = &l.rgb[(static_cast<size_t>(y) * l.width + x) * 3];
  return Eigen::Vector3f(p[0], p[1], p[2]);
}

Eigen::Vector3f Texture::SampleLevel(double u, double v, int level) const {
  const Level& l = levels_[level];
  const double scale = 1.0 / static_cast<double>(1 << level);
  // Texel centres sit at +0.5.
  const double x = u * scale - 0.5;
  const double y = v * scale - 0.5;
  const double fx = std::floor(x), fy = std::floor(y);
  const float ax = static_cast<float>(x - fx), ay = static_cast<float>(y - fy);
  const int x0 = std::clamp(static_cast<int>(fx), 0, l.width - 1);
  const int x1 = std::clamp(static_cast<int>(fx) + 1, 0, l.width - 1);
  const int y0 = std::clamp(static_cast<int>(fy), 0, l.height - 1);
  const int y1 = std::clamp(static_cast<int>(fy) + 1, 0, l.height - 1);
  const float* p00 = &l.rgb[(static_cast<size_t>(y0) * l.width + x0) * 3];
  const float* p10 = &l.rgb[(static_cast<size_t>(y0) * l.width + x1) * 3];
  const float* p01 = &l.rgb[(static_cast<size_t>(y1) * l.width + x0) * 3];
  const float* p11 = &l.rgb[(static_cast<size_t>(y1) * l.width + x1) * 3];
  Eigen::Vector3f out;
  for (int c = 0; c < 3; ++c) {
    const float top = p00[c] + ax * (p10[c] - p00[c]);
    const float bottom = p01[c] + ax * (p11[c] - p01[c]);
    out[c] = top + ay * (bottom - top);
  }
  return out;
}

Eigen::Vector3f Texture::Sample(double u, double v, double level) const {
  const int last = num_levels() - 1;
  if (!(level > 0.0)) return SampleLevel(u, v, 0);
  if (level >= last) return SampleLevel(u, v, last);
  const int lower = static_cast<int>(level);
  const float blend = static_cast<float>(level - lower);
  Eigen::Vector3f a = SampleLevel(u, v, lower);
  if (blend <= 0.0f) return a;
  return a + blend * (SampleLevel(u, v, lower + 1) - a);
}

}  // namespace odomcal
