// Per octave: draw a (lattice_w + 2) x (lattice_h + 2) x 3 grid of uniform
// values in [-1, 1] and a random offset in [0, period); every texel centre
// adds the smoothstep-interpolated lattice value. Finally each channel is
// shifted and scaled to the requested mean and contrast.

#include "odomcal/datasets/rendering/value_noise.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace odomcal {
namespace {

bool IsPowerOfTwo(int n) { return n >= 1 && (n & (n - 1)) == 0; }

}  // namespace

void ValueNoiseOptions::Check() const {
  if (width <= 0 || height <= 0) {
    throw std::invalid_argument("ValueNoiseOptions: width/height must be > 0");
  }
  if (!IsPowerOfTwo(min_period_texels)) {
    throw std::invalid_argument(
        "ValueNoiseOptions.min_period_texels must be a power of two, got " +
        std::to_string(min_period_texels));
  }
  if (!IsPowerOfTwo(max_period_texels) ||
      max_period_texels < min_period_texels) {
    throw std::invalid_argument(
        "ValueNoiseOptions.max_period_texels must be a power of two >= "
        "min_period_texels, got " +
        std::to_string(max_period_texels));
  }
  if (!(channel_stddev > 0.0)) {
    throw std::invalid_argument("ValueNoiseOptions.channel_stddev must be > 0");
  }
}

Texture MakeValueNoiseTexture(const ValueNoiseOptions& options) {
  options.Check();
  const int w = options.width, h = options.height;
  std::vector<float> rgb(static_cast<size_t>(w) * h * 3, 0.0f);
  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<float> value(-1.0f, 1.0f);
  std::vector<float> weights, lattice;
  std::vector<int> cells;
  for (int period = options.min_period_texels;
       period <= options.max_period_texels;
       period *= 2) {
    const double offset_x =
        std::uniform_real_distribution<double>(0, period)(rng);
    const double offset_y =
        std::uniform_real_distribution<double>(0, period)(rng);
    const int lw = static_cast<int>(std::ceil((w + offset_x) / period)) + 2;
    const int lh = static_cast<int>(std::ceil((h + offset_y) / period)) + 2;
    lattice.resize(static_cast<size_t>(lw) * lh * 3);
    for (float& x : lattice) x = value(rng);
    // Interpolation weights along x are the same for every row.
    cells.resize(w);
    weights.resize(w);
    for (int x = 0; x < w; ++x) {
      const double fx = (x + 0.5 + offset_x) / period;
      cells[x] = static_cast<int>(fx);
      const double t = fx - cells[x];
      weights[x] = static_cast<float>(t * t * (3.0 - 2.0 * t));
    }
    for (int y = 0; y < h; ++y) {
      const double fy = (y + 0.5 + offset_y) / period;
      const int cy = static_cast<int>(fy);
      const double ty = fy - cy;
      const float sy = static_cast<float>(ty * ty * (3.0 - 2.0 * ty));
      const float* row0 = &lattice[static_cast<size_t>(cy) * lw * 3];
      const float* row1 = row0 + static_cast<size_t>(lw) * 3;
      float* out = &rgb[static_cast<size_t>(y) * w * 3];
      for (int x = 0; x < w; ++x) {
        const int c0 = cells[x] * 3;
        const float sx = weights[x];
        for (int c = 0; c < 3; ++c) {
          const float top =
              row0[c0 + c] + sx * (row0[c0 + 3 + c] - row0[c0 + c]);
          const float bottom =
              row1[c0 + c] + sx * (row1[c0 + 3 + c] - row1[c0 + c]);
          out[3 * x + c] += top + sy * (bottom - top);
        }
      }
    }
  }
  // Normalise each channel to mean 0.5 and the requested contrast.
  for (int c = 0; c < 3; ++c) {
    double sum = 0.0, sum_sq = 0.0;
    const size_t n = static_cast<size_t>(w) * h;
    for (size_t i = 0; i < n; ++i) {
      sum += rgb[3 * i + c];
      sum_sq += static_cast<double>(rgb[3 * i + c]) * rgb[3 * i + c];
    }
    const double mean = sum / n;
    const double stddev = std::sqrt(std::max(sum_sq / n - mean * mean, 1e-12));
    const double gain = options.channel_stddev / stddev;
    for (size_t i = 0; i < n; ++i) {
      const double v = 0.5 + gain * (rgb[3 * i + c] - mean);
      rgb[3 * i + c] = static_cast<float>(std::clamp(v, 0.0, 1.0));
    }
  }
  return Texture(w, h, std::move(rgb));
}

}  // namespace odomcal
