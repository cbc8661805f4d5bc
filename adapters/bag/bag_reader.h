// Robot recordings read message by message: ROS 1 bags (format 2.0) and ROS 2
// bags (a rosbag2 folder with metadata.yaml, or one .db3 or .mcap file).
//
// Readers stream: memory stays bounded by one chunk and one message, whatever
// the bag's size. Messages come in storage order (for ROS 1 the chunks' order,
// for MCAP the chunks' order, for SQLite the time stamp order), which is close
// to but not always log-time order; consumers that need order sort by stamp.
// Times are integer nanoseconds since the Unix epoch.
//
// Every problem with the file (truncated, unindexed and unscannable, unknown
// storage or compression, a record that does not parse) throws FormatError
// with one line that starts with the file path.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace odomcal::bag {

// How a message's bytes are laid out on the wire.
enum class MessageEncoding {
  kRos1,  // ROS 1 serialization: little-endian, packed, no alignment
  kCdr,   // ROS 2: OMG CDR with a 4-byte encapsulation header
};

struct BagTopic {
  std::string topic;
  // The message type as "package/Name" for both ROS versions (ROS 2's
  // "package/msg/Name" is normalised), e.g. "sensor_msgs/Image".
  std::string type;
  MessageEncoding encoding = MessageEncoding::kRos1;
  int64_t message_count = 0;
  // Log (record) times of the first and last message; 0 when count is 0.
  int64_t first_log_time_ns = 0;
  int64_t last_log_time_ns = 0;
};

struct BagMessage {
  // Index into BagReader::Topics().
  size_t topic_index = 0;
  // When the recorder received the message (the bag's own time stamp).
  int64_t log_time_ns = 0;
  // The serialized message (for kCdr including its encapsulation header).
  std::vector<uint8_t> data;
};

// Adds `more`'s messages (count and time span) to `*topic`, the same topic
// seen in another channel or file.
inline void AddMessagesOf(const BagTopic& more, BagTopic* topic) {
  if (more.message_count == 0) return;
  if (topic->message_count == 0 ||
      more.first_log_time_ns < topic->first_log_time_ns) {
    topic->first_log_time_ns = more.first_log_time_ns;
  }
  if (topic->message_count == 0 ||
      more.last_log_time_ns > topic->last_log_time_ns) {
    topic->last_log_time_ns = more.last_log_time_ns;
  }
  topic->message_count += more.message_count;
}

class BagReader {
 public:
  virtual ~BagReader() = default;

  // The file or folder that was opened, for messages.
  virtual const std::string& Path() const = 0;
  // Every topic in the bag, with counts and time spans from the bag's index
  // or summary (or from a scan where the format has none).
  virtual const std::vector<BagTopic>& Topics() const = 0;
  // The next message of a selected topic into *message; false at the end.
  virtual bool Next(BagMessage* message) = 0;
};

// Opens a bag and selects the topics whose messages Next() returns (all when
// `topics` is empty; an unknown topic name throws FormatError naming it).
// The format is recognised by content (ROS 1's "#ROSBAG V2.0" magic, MCAP's
// magic, SQLite's header) or a folder's metadata.yaml, not by the name.
std::unique_ptr<BagReader> OpenBag(const std::string& path,
                                   const std::vector<std::string>& topics = {});

}  // namespace odomcal::bag
