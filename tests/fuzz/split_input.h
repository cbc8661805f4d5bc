// One fuzz input holding several files, for parsers that read a folder.
//
// The parts are separated by kFileSeparator ("@@ODOMCAL-FILE@@"), a marker
// that libFuzzer learns quickly from the dictionary (tests/fuzz/*.dict) and
// that people can type when writing a seed by hand:
//   <cameras.bin bytes>@@ODOMCAL-FILE@@<images.bin bytes>@@ODOMCAL-FILE@@<...>
// Missing parts are empty; the last part takes the rest of the input, marker
// and all, so every input maps to exactly one set of files.
#pragma once

#include <array>
#include <cstddef>
#include <string_view>

namespace odomcal {

inline constexpr std::string_view kFileSeparator = "@@ODOMCAL-FILE@@";

template <size_t kNumParts>
std::array<std::string_view, kNumParts> SplitInput(std::string_view input) {
  std::array<std::string_view, kNumParts> parts;
  for (size_t i = 0; i + 1 < kNumParts; ++i) {
    const size_t end = input.find(kFileSeparator);
    if (end == std::string_view::npos) {
      parts[i] = input;
      return parts;
    }
    parts[i] = input.substr(0, end);
    input.remove_prefix(end + kFileSeparator.size());
  }
  parts[kNumParts - 1] = input;
  return parts;
}

}  // namespace odomcal
