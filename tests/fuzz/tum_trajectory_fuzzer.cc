// Fuzzes ReadTumTrajectory: the input is written to a scratch file and read
// in every TimeUnit (the unit changes which timestamps are in range).
//
// Expected outcome for malformed input: FormatError. Anything else (a crash,
// a sanitizer report, any other exception) escapes and is a finding.
#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/trajectory_io.h"

#include "scratch_dir.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const odomcal::ScratchDir scratch;
  const std::string path =
      scratch.Write("poses.tum", odomcal::AsBytes(data, size));
  for (const odomcal::TimeUnit unit : {odomcal::TimeUnit::kSeconds,
                                       odomcal::TimeUnit::kMilliseconds,
                                       odomcal::TimeUnit::kMicroseconds,
                                       odomcal::TimeUnit::kNanoseconds}) {
    try {
      odomcal::ReadTumTrajectory(path, unit);
    } catch (const odomcal::FormatError&) {
    }
  }
  return 0;
}
