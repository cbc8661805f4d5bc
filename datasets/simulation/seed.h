// Independent random streams from one user-visible seed.
#pragma once

#include <cstdint>

namespace odomcal {

// SplitMix64 of (seed, stream): decorrelated seeds for the parts of a
// simulation (scene, path, noise...), so changing one part's use of random
// numbers does not change the others.
inline uint64_t DeriveSeed(uint64_t seed, uint64_t stream) {
  uint64_t z = seed + 0x9E3779B97F4A7C15ull * (stream + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace odomcal
