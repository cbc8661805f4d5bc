// Fuzzes the image timestamp sources: ReadImageTimestampsCsv on the input
// written to a scratch file, in every TimeUnit, and TimestampFromImageName
// on each line of the input taken as an image name, with and without a unit.
//
// Expected outcome for malformed input: FormatError from the CSV reader and
// std::nullopt from the name rule. Anything else (a crash, a sanitizer
// report, any other exception) escapes and is a finding.
#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/image_timestamps.h"

#include "scratch_dir.h"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const odomcal::ScratchDir scratch;
  const std::string_view input = odomcal::AsBytes(data, size);
  const std::string path = scratch.Write("stamps.csv", input);
  const odomcal::TimeUnit units[] = {odomcal::TimeUnit::kSeconds,
                                     odomcal::TimeUnit::kMilliseconds,
                                     odomcal::TimeUnit::kMicroseconds,
                                     odomcal::TimeUnit::kNanoseconds};
  for (const odomcal::TimeUnit unit : units) {
    try {
      odomcal::ReadImageTimestampsCsv(path, unit);
    } catch (const odomcal::FormatError&) {
    }
  }

  size_t begin = 0;
  while (begin <= input.size()) {
    size_t end = input.find('\n', begin);
    if (end == std::string_view::npos) end = input.size();
    const std::string name(input.substr(begin, end - begin));
    std::string error;
    odomcal::TimestampFromImageName(name, std::nullopt, &error);
    for (const odomcal::TimeUnit unit : units) {
      odomcal::TimestampFromImageName(name, unit, &error);
    }
    begin = end + 1;
  }
  return 0;
}
