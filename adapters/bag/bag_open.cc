// OpenBag: the reader for a bag's format, recognised by content.
#include "odomcal/adapters/bag/bag_reader.h"
#include "odomcal/adapters/bag/ros1_bag_reader.h"
#include "odomcal/adapters/bag/ros2_bag_reader.h"
#include "odomcal/adapters/format_error.h"

#include <filesystem>
#include <system_error>

namespace odomcal::bag {

std::unique_ptr<BagReader> OpenBag(const std::string& path,
                                   const std::vector<std::string>& topics) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) {
    throw FormatError(path + ": no such file or folder");
  }
  if (LooksLikeRos1Bag(path)) return OpenRos1Bag(path, topics);
  if (LooksLikeRos2Bag(path)) return OpenRos2Bag(path, topics);
  throw FormatError(
      path +
      ": not a robot bag odomcal reads (a ROS 1 bag starts with "
      "'#ROSBAG V2.0'; a ROS 2 bag is a folder with metadata.yaml, an MCAP "
      "file or a SQLite .db3 file)");
}

}  // namespace odomcal::bag
