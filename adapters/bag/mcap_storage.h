// MCAP storage (https://mcap.dev/spec, rosbag2_storage_mcap's profile "ros2"):
// schemas, channels and messages at the top level or in chunks (uncompressed,
// zstd or lz4); internal: not installed.
#pragma once

#include "odomcal/adapters/bag/ros2_storage.h"

#include <memory>
#include <string>

namespace odomcal::bag::internal {

// Opens the file and reads its topics: from the summary section (channels,
// schemas, and the message indexes for the counts and time spans) when the
// file has one, else by scanning the data section up to its last complete
// record (a recording that was killed). Throws FormatError ("path: ...").
std::unique_ptr<Ros2Storage> OpenMcapStorage(const std::string& path);

// True when the file starts with MCAP's magic "\x89MCAP0\r\n".
bool LooksLikeMcapFile(const std::string& path);

}  // namespace odomcal::bag::internal
