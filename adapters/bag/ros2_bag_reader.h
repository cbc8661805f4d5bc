// ROS 2 bags (rosbag2): a folder with metadata.yaml and its storage files, or
// one storage file: SQLite (.db3, rosbag2_storage_default_plugins' schema) or
// MCAP (https://mcap.dev/spec; chunks uncompressed, zstd or lz4). Messages are
// CDR; a bag split into several files is read file after file.
#pragma once

#include "odomcal/adapters/bag/bag_reader.h"

#include <memory>
#include <string>
#include <vector>

namespace odomcal::bag {

// True for a folder with metadata.yaml, a SQLite file or an MCAP file.
bool LooksLikeRos2Bag(const std::string& path);

std::unique_ptr<BagReader> OpenRos2Bag(const std::string& path,
                                       const std::vector<std::string>& topics);

}  // namespace odomcal::bag
