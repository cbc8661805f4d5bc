// Fuzzes the ROS 2 bag reader on MCAP files: the input is written to a
// scratch file bag.mcap, which OpenRos2Bag opens (recognised by content, so
// inputs that lose the magic exercise the SQLite and "not a bag" paths too)
// and reads message by message, as the calibration does.
//
// Expected outcome for malformed input: FormatError (bad magic, truncated
// records, lengths past the end, unknown compression, CRC mismatch, corrupt
// zstd or lz4 frames). Anything else (a crash, a sanitizer report, an
// allocation that a forged length caused, any other exception) escapes and
// is a finding.
#include "odomcal/adapters/bag/ros2_bag_reader.h"
#include "odomcal/adapters/format_error.h"

#include "scratch_dir.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const odomcal::ScratchDir scratch;
  const std::string path =
      scratch.Write("bag.mcap", odomcal::AsBytes(data, size));
  try {
    const auto reader = odomcal::bag::OpenRos2Bag(path, {});
    odomcal::bag::BagMessage message;
    while (reader->Next(&message)) {
    }
  } catch (const odomcal::FormatError&) {
  }
  return 0;
}
