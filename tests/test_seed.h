// Deterministic, visible seeds for randomized tests. ODOMCAL_TEST_SEED
// overrides the default so a failure can be replayed or other seeds explored.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <random>
#include <string>

namespace odomcal {

inline uint64_t TestSeed(uint64_t default_seed) {
  const char* env = std::getenv("ODOMCAL_TEST_SEED");
  return env != nullptr ? std::strtoull(env, nullptr, 10) : default_seed;
}

// Usage: auto rng = SeededRng(7); SCOPED_TRACE is added by the caller.
inline std::mt19937_64 SeededRng(uint64_t default_seed) {
  return std::mt19937_64(TestSeed(default_seed));
}

}  // namespace odomcal
