// Multi-scale colour value noise: the texture the renderer puts on surfaces.
//
// Each colour channel is a sum of octaves; octave k has random values on a
// square lattice of period p_k texels (p = min_period .. max_period, doubling),
// interpolated with a smoothstep, each octave with its own random lattice
// offset. Lattice values come from one seeded generator and are never
// re-used, so the texture does not repeat at any shift (only edge clamping
// beyond its size). Every octave has the same amplitude, so there is
// high-contrast detail from 2 texels to 256 texels; each channel is then
// normalised to mean 0.5 and standard deviation `channel_stddev`, clamped to
// [0, 1]. Why: SIFT finds features at all scales and sequential matching does
// not confuse places (checkerboards and low-frequency noise fail in COLMAP).
//
// Deterministic for (width, height, seed, periods, stddev).
#pragma once

#include "odomcal/datasets/rendering/texture.h"

#include <cstdint>

namespace odomcal {

struct ValueNoiseOptions {
  int width = 512;   // texels
  int height = 512;  // texels
  uint64_t seed = 0;
  int min_period_texels = 2;     // finest octave, a power of two >= 1
  int max_period_texels = 256;   // coarsest octave, a power of two >= min
  double channel_stddev = 0.22;  // contrast after normalisation
  void Check() const;  // throws std::invalid_argument naming the field
};

Texture MakeValueNoiseTexture(const ValueNoiseOptions& options);

}  // namespace odomcal
