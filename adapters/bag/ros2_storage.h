// One storage file of a ROS 2 bag (a .db3 or an .mcap), as ros2_bag_reader.cc
// sees it: the file's topics, then its messages in storage order. A split bag
// is several of these read one after the other; internal: not installed.
#pragma once

#include "odomcal/adapters/bag/bag_reader.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace odomcal::bag::internal {

struct Ros2StorageTopic {
  // encoding is kCdr; the counts and times are this file's.
  BagTopic topic;
  // Why the topic's messages cannot be read as ROS 2 CDR (a message encoding
  // other than "cdr", a schema that is not a ROS 2 one); empty when they can.
  // The reader refuses only when such a topic is selected.
  std::string refusal;
};

class Ros2Storage {
 public:
  virtual ~Ros2Storage() = default;

  virtual const std::vector<Ros2StorageTopic>& Topics() const = 0;
  // Which of Topics() Next() returns (one flag per topic; all by default).
  virtual void Select(const std::vector<bool>& selected) = 0;
  // The next selected message; topic_index indexes this file's Topics().
  virtual bool Next(BagMessage* message) = 0;
};

// "sensor_msgs/msg/Image" -> "sensor_msgs/Image"; other names unchanged.
std::string NormaliseRos2Type(const std::string& type);

// A name read from a file, for a one-line message: in single quotes, bytes
// outside printable ASCII as \xNN, cut after 100 characters.
std::string Ros2Quoted(const std::string& text);

}  // namespace odomcal::bag::internal
