// ROS 1 bags, format 2.0 (http://wiki.ros.org/Bags/Format/2.0): chunks
// uncompressed, bz2 or lz4; read through the index at the end of the file, or
// by scanning the chunks when the bag was not closed (no index).
#pragma once

#include "odomcal/adapters/bag/bag_reader.h"

#include <memory>
#include <string>
#include <vector>

namespace odomcal::bag {

// True when the file starts with "#ROSBAG V2.0\n".
bool LooksLikeRos1Bag(const std::string& path);

std::unique_ptr<BagReader> OpenRos1Bag(const std::string& path,
                                       const std::vector<std::string>& topics);

}  // namespace odomcal::bag
