// The ROS 1 bag reader. A closed bag is read through its index: the bag
// header's index_pos points at the connection records and one chunk info per
// chunk (its position and message count per connection); the index data
// records right after each chunk give each connection's message times. A bag
// whose recorder died has index_pos 0; it is read by scanning its
// chunks, up to the chunk the recorder left open or cut off.
#include "odomcal/adapters/bag/ros1_bag_reader.h"

#include "odomcal/adapters/bag/ros1_bag_records.h"
#include "odomcal/adapters/bag/ros1_chunk_codec.h"
#include "odomcal/adapters/format_error.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <system_error>

namespace odomcal::bag {
namespace {

constexpr char kRos1Magic[] = "#ROSBAG V2.0\n";
constexpr size_t kRos1MagicSize = sizeof(kRos1Magic) - 1;
// Record headers hold a few short fields; a longer one is corrupt.
constexpr uint32_t kRos1MaxRecordHeaderBytes = 1u << 20;

// A record read from the file: its header, and where its data lie.
struct Ros1FileRecord {
  Ros1RecordHeader header;
  uint64_t data_pos = 0;
  uint32_t data_size = 0;
  uint64_t end = 0;
};

// Random access to the bag file with every read checked against its size.
class Ros1File {
 public:
  explicit Ros1File(const std::string& path) {
    std::error_code ignored;
    if (std::filesystem::is_directory(path, ignored)) {
      throw FormatError(path + ": is a folder, not a ROS 1 bag file");
    }
    stream_.open(path, std::ios::binary);
    if (!stream_) {
      throw FormatError(path +
                        ": cannot open for reading: " + std::strerror(errno));
    }
    stream_.seekg(0, std::ios::end);
    const std::streamoff end = stream_.tellg();
    if (end < 0) throw FormatError(path + ": cannot read the file size");
    size_ = static_cast<uint64_t>(end);
  }

  uint64_t size() const { return size_; }

  // Reads bytes [pos, pos + count); FormatError when they are not all there.
  void Read(uint64_t pos, size_t count, uint8_t* out) {
    if (pos > size_ || count > size_ - pos) {
      throw FormatError("file ends at byte " + std::to_string(size_) + ", " +
                        std::to_string(count) + " bytes needed from byte " +
                        std::to_string(pos));
    }
    stream_.clear();
    stream_.seekg(static_cast<std::streamoff>(pos));
    stream_.read(reinterpret_cast<char*>(out),
                 static_cast<std::streamsize>(count));
    if (!stream_)
      throw FormatError("read error at byte " + std::to_string(pos));
  }

  // Reads the record header at `pos` and locates its data.
  Ros1FileRecord ReadRecord(uint64_t pos) {
    uint8_t length[4];
    Read(pos, 4, length);
    const uint32_t header_size = Ros1LoadU32(length);
    if (header_size > kRos1MaxRecordHeaderBytes ||
        header_size > size_ - pos - 4) {
      throw FormatError("record header length " + std::to_string(header_size) +
                        " runs past the end of the file (" +
                        std::to_string(size_) + " bytes)");
    }
    std::vector<uint8_t> header(header_size);
    Read(pos + 4, header_size, header.data());
    Ros1FileRecord record;
    record.header = Ros1RecordHeader::Parse(header.data(), header.size());
    Read(pos + 4 + header_size, 4, length);
    record.data_pos = pos + 8 + header_size;
    record.data_size = Ros1LoadU32(length);
    if (record.data_size > size_ - record.data_pos) {
      throw FormatError("record data length " +
                        std::to_string(record.data_size) +
                        " runs past the end of the file (" +
                        std::to_string(size_) + " bytes)");
    }
    record.end = record.data_pos + record.data_size;
    return record;
  }

  // True when a whole record starts at `pos` (its lengths stay in the file).
  bool HasWholeRecord(uint64_t pos) {
    if (pos > size_ || size_ - pos < 8) return false;
    uint8_t length[4];
    Read(pos, 4, length);
    const uint64_t header_size = Ros1LoadU32(length);
    if (header_size + 8 > size_ - pos) return false;
    Read(pos + 4 + header_size, 4, length);
    return Ros1LoadU32(length) <= size_ - pos - 8 - header_size;
  }

 private:
  std::ifstream stream_;
  uint64_t size_ = 0;
};

std::string Ros1At(uint64_t pos) { return "byte " + std::to_string(pos); }

std::string Ros1Printable(const std::string& text) {
  std::string out;
  for (const char c : text.substr(0, 200))
    out += (c >= 0x20 && c < 0x7f) ? c : '?';
  return out;
}

void Ros1ExpectOp(const Ros1RecordHeader& header,
                  uint8_t op,
                  const char* what) {
  const uint8_t got = header.Op();
  if (got != op) {
    throw FormatError(std::string("expected ") + what + " (op " +
                      std::to_string(op) + "), found op " +
                      std::to_string(got));
  }
}

// A connection: the topic and type its messages belong to.
struct Ros1Connection {
  std::string topic;
  std::string type;
};

Ros1Connection Ros1ParseConnection(const Ros1RecordHeader& header,
                                   const uint8_t* data,
                                   size_t data_size) {
  const Ros1RecordHeader fields = Ros1RecordHeader::Parse(data, data_size);
  Ros1Connection connection;
  connection.topic = header.String("topic");
  connection.type = fields.String("type");
  if (connection.topic.empty())
    throw FormatError("connection with an empty topic name");
  return connection;
}

class Ros1BagReader : public BagReader {
 public:
  Ros1BagReader(const std::string& path, const std::vector<std::string>& topics)
      : path_(path), file_(path) {
    try {
      Open();
    } catch (const FormatError& e) {
      throw FormatError(path_ + ": " + e.what());
    }
    Select(topics);
  }

  const std::string& Path() const override { return path_; }
  const std::vector<BagTopic>& Topics() const override { return topics_; }

  bool Next(BagMessage* message) override {
    try {
      return NextInChunks(message);
    } catch (const FormatError& e) {
      throw FormatError(path_ + ": chunk at " +
                        Ros1At(chunks_[next_chunk_ - 1]) + ": " + e.what());
    }
  }

 private:
  // Per connection, what the index or a scan says about its messages.
  struct Ros1ConnectionStats {
    int64_t count = 0;
    int64_t first_ns = std::numeric_limits<int64_t>::max();
    int64_t last_ns = std::numeric_limits<int64_t>::min();
  };

  void Open() {
    uint8_t magic[kRos1MagicSize];
    if (file_.size() < kRos1MagicSize) {
      throw FormatError(
          "not a ROS bag: too short for the \"#ROSBAG V2.0\" line");
    }
    file_.Read(0, kRos1MagicSize, magic);
    if (std::memcmp(magic, kRos1Magic, kRos1MagicSize) != 0) {
      if (std::memcmp(magic, "#ROSBAG V", 9) == 0) {
        throw FormatError("ROS bag format " +
                          Ros1Printable(std::string(magic + 9, magic + 12)) +
                          " is not supported, only 2.0");
      }
      throw FormatError("not a ROS bag: no \"#ROSBAG V2.0\" line");
    }
    Ros1FileRecord bag_header;
    try {
      bag_header = file_.ReadRecord(kRos1MagicSize);
      Ros1ExpectOp(bag_header.header, kRos1OpBagHeader, "the bag header");
    } catch (const FormatError& e) {
      throw FormatError("bag header: " + std::string(e.what()));
    }
    const uint64_t index_pos = bag_header.header.UInt64("index_pos");
    first_record_ = bag_header.end;
    std::map<uint32_t, Ros1ConnectionStats> stats;
    if (index_pos == 0) {
      Scan(&stats);
    } else {
      ReadIndex(index_pos, &stats);
      // A file cut exactly at index_pos would otherwise read as an empty bag.
      const uint32_t chunk_count = bag_header.header.UInt32("chunk_count");
      const uint32_t conn_count = bag_header.header.UInt32("conn_count");
      if (chunks_.size() != chunk_count || connections_.size() != conn_count) {
        throw FormatError("the index holds " + std::to_string(chunks_.size()) +
                          " chunks and " + std::to_string(connections_.size()) +
                          " connections, the bag header says " +
                          std::to_string(chunk_count) + " and " +
                          std::to_string(conn_count) + " (truncated?)");
      }
    }
    BuildTopics(stats);
  }

  void AddConnection(uint32_t id, const Ros1Connection& connection) {
    const auto known = connections_.find(id);
    if (known != connections_.end()) {
      if (known->second.topic != connection.topic ||
          known->second.type != connection.type) {
        throw FormatError("connection " + std::to_string(id) +
                          " is declared twice, as '" +
                          Ros1Printable(known->second.topic) + "' and '" +
                          Ros1Printable(connection.topic) + "'");
      }
      return;
    }
    connections_.emplace(id, connection);
  }

  // The closed bag: connections and chunk infos at index_pos, then the index
  // data records after each chunk for the times.
  void ReadIndex(uint64_t index_pos,
                 std::map<uint32_t, Ros1ConnectionStats>* stats) {
    if (index_pos < first_record_ || index_pos > file_.size()) {
      throw FormatError("index position " + std::to_string(index_pos) +
                        " is outside the file (" +
                        std::to_string(file_.size()) + " bytes)");
    }
    std::map<uint64_t, std::map<uint32_t, uint32_t>> chunk_counts;
    for (uint64_t pos = index_pos; pos < file_.size();) {
      try {
        const Ros1FileRecord record = file_.ReadRecord(pos);
        const uint8_t op = record.header.Op();
        if (op == kRos1OpConnection) {
          std::vector<uint8_t> data(record.data_size);
          file_.Read(record.data_pos, data.size(), data.data());
          AddConnection(
              record.header.UInt32("conn"),
              Ros1ParseConnection(record.header, data.data(), data.size()));
        } else if (op == kRos1OpChunkInfo) {
          ReadChunkInfo(record, &chunk_counts);
        } else {
          throw FormatError("unexpected op " + std::to_string(op) +
                            " in the index");
        }
        pos = record.end;
      } catch (const FormatError& e) {
        throw FormatError("index record at " + Ros1At(pos) + ": " + e.what());
      }
    }
    for (const auto& [chunk_pos, counts] : chunk_counts) {
      if (chunk_pos < first_record_ || chunk_pos >= index_pos) {
        throw FormatError("chunk info points at " + Ros1At(chunk_pos) +
                          ", outside the chunks' bytes " +
                          std::to_string(first_record_) + "-" +
                          std::to_string(index_pos));
      }
      try {
        ReadChunkTimes(chunk_pos, counts, stats);
      } catch (const FormatError& e) {
        throw FormatError("chunk at " + Ros1At(chunk_pos) + ": " + e.what());
      }
      chunks_.push_back(chunk_pos);
    }
  }

  void ReadChunkInfo(
      const Ros1FileRecord& record,
      std::map<uint64_t, std::map<uint32_t, uint32_t>>* chunk_counts) {
    if (record.header.UInt32("ver") != 1) {
      throw FormatError("chunk info version " +
                        std::to_string(record.header.UInt32("ver")) +
                        " is not 1");
    }
    const uint64_t chunk_pos = record.header.UInt64("chunk_pos");
    const uint32_t count = record.header.UInt32("count");
    if (static_cast<uint64_t>(count) * 8 != record.data_size) {
      throw FormatError("chunk info lists " + std::to_string(count) +
                        " connections in " + std::to_string(record.data_size) +
                        " bytes");
    }
    std::vector<uint8_t> data(record.data_size);
    file_.Read(record.data_pos, data.size(), data.data());
    auto& counts = (*chunk_counts)[chunk_pos];
    for (uint32_t i = 0; i < count; ++i) {
      counts[Ros1LoadU32(&data[size_t{8} * i])] +=
          Ros1LoadU32(&data[size_t{8} * i + 4]);
    }
  }

  // Skips the chunk at chunk_pos and reads the index data records after it.
  void ReadChunkTimes(uint64_t chunk_pos,
                      const std::map<uint32_t, uint32_t>& counts,
                      std::map<uint32_t, Ros1ConnectionStats>* stats) {
    const Ros1FileRecord chunk = file_.ReadRecord(chunk_pos);
    Ros1ExpectOp(chunk.header, kRos1OpChunk, "a chunk");
    std::map<uint32_t, uint32_t> indexed;
    uint64_t pos = chunk.end;
    while (indexed.size() < counts.size()) {
      const Ros1FileRecord record = file_.ReadRecord(pos);
      Ros1ExpectOp(record.header, kRos1OpIndexData, "the chunk's index data");
      if (record.header.UInt32("ver") != 1) {
        throw FormatError("index data version " +
                          std::to_string(record.header.UInt32("ver")) +
                          " is not 1");
      }
      const uint32_t id = record.header.UInt32("conn");
      const uint32_t count = record.header.UInt32("count");
      if (static_cast<uint64_t>(count) * 12 != record.data_size) {
        throw FormatError("index data lists " + std::to_string(count) +
                          " messages in " + std::to_string(record.data_size) +
                          " bytes");
      }
      const auto expected = counts.find(id);
      if (expected == counts.end() || expected->second != count ||
          indexed.count(id) != 0) {
        throw FormatError("index data of connection " + std::to_string(id) +
                          " disagree with the chunk info");
      }
      std::vector<uint8_t> data(record.data_size);
      file_.Read(record.data_pos, data.size(), data.data());
      Ros1ConnectionStats& s = (*stats)[id];
      for (uint32_t i = 0; i < count; ++i) {
        const int64_t t = Ros1TimeNs(&data[size_t{12} * i]);
        s.first_ns = std::min(s.first_ns, t);
        s.last_ns = std::max(s.last_ns, t);
      }
      s.count += count;
      indexed[id] = count;
      pos = record.end;
    }
  }

  // The unclosed bag: every chunk in turn, decompressed for its connection
  // and message records. A record cut off by the end of the file, or a chunk
  // still marked open (data length 0), is where the recording stopped.
  void Scan(std::map<uint32_t, Ros1ConnectionStats>* stats) {
    std::vector<uint8_t> compressed;
    std::vector<uint8_t> chunk;
    for (uint64_t pos = first_record_; file_.HasWholeRecord(pos);) {
      try {
        const Ros1FileRecord record = file_.ReadRecord(pos);
        const uint8_t op = record.header.Op();
        if (op == kRos1OpChunk) {
          if (record.data_size == 0) break;
          compressed.resize(record.data_size);
          file_.Read(record.data_pos, compressed.size(), compressed.data());
          Ros1DecompressChunk(record.header.String("compression"),
                              compressed,
                              record.header.UInt32("size"),
                              &chunk);
          ScanChunk(chunk, stats);
          chunks_.push_back(pos);
        } else if (op != kRos1OpIndexData && op != kRos1OpConnection &&
                   op != kRos1OpChunkInfo) {
          throw FormatError("unexpected op " + std::to_string(op));
        }
        pos = record.end;
      } catch (const FormatError& e) {
        throw FormatError("bag without index, record at " + Ros1At(pos) + ": " +
                          e.what());
      }
    }
  }

  void ScanChunk(const std::vector<uint8_t>& chunk,
                 std::map<uint32_t, Ros1ConnectionStats>* stats) {
    for (size_t offset = 0; offset < chunk.size();) {
      const Ros1BufferRecord record =
          Ros1ReadBufferRecord(chunk.data(), chunk.size(), offset);
      const uint8_t op = record.header.Op();
      if (op == kRos1OpConnection) {
        AddConnection(
            record.header.UInt32("conn"),
            Ros1ParseConnection(record.header, record.data, record.data_size));
      } else if (op == kRos1OpMessageData) {
        const uint32_t id = record.header.UInt32("conn");
        if (connections_.count(id) == 0) {
          throw FormatError("message on connection " + std::to_string(id) +
                            ", which no connection record declares");
        }
        const int64_t t = record.header.TimeNs("time");
        Ros1ConnectionStats& s = (*stats)[id];
        ++s.count;
        s.first_ns = std::min(s.first_ns, t);
        s.last_ns = std::max(s.last_ns, t);
      } else {
        throw FormatError("unexpected op " + std::to_string(op) +
                          " inside a chunk");
      }
      offset = record.end;
    }
  }

  // One BagTopic per topic name (a topic recorded from several publishers
  // has one connection each), sorted by name.
  void BuildTopics(const std::map<uint32_t, Ros1ConnectionStats>& stats) {
    std::map<std::string, BagTopic> by_name;
    for (const auto& [id, connection] : connections_) {
      BagTopic& topic = by_name[connection.topic];
      if (topic.topic.empty()) {
        topic.topic = connection.topic;
        topic.type = connection.type;
        topic.encoding = MessageEncoding::kRos1;
      } else if (topic.type != connection.type) {
        throw FormatError("topic '" + Ros1Printable(connection.topic) +
                          "' has two types, " + Ros1Printable(topic.type) +
                          " and " + Ros1Printable(connection.type));
      }
      const auto s = stats.find(id);
      if (s == stats.end() || s->second.count == 0) continue;
      if (topic.message_count == 0) {
        topic.first_log_time_ns = s->second.first_ns;
        topic.last_log_time_ns = s->second.last_ns;
      } else {
        topic.first_log_time_ns =
            std::min(topic.first_log_time_ns, s->second.first_ns);
        topic.last_log_time_ns =
            std::max(topic.last_log_time_ns, s->second.last_ns);
      }
      topic.message_count += s->second.count;
    }
    for (const auto& [id, count] : stats) {
      if (connections_.count(id) == 0) {
        throw FormatError("the index counts messages of connection " +
                          std::to_string(id) +
                          ", which no connection record declares");
      }
    }
    std::map<std::string, size_t> index_of_topic;
    for (auto& [name, topic] : by_name) {
      index_of_topic[name] = topics_.size();
      topics_.push_back(std::move(topic));
    }
    for (const auto& [id, connection] : connections_) {
      topic_of_connection_[id] = index_of_topic.at(connection.topic);
    }
  }

  void Select(const std::vector<std::string>& names) {
    selected_.assign(topics_.size(), names.empty());
    for (const std::string& name : names) {
      const auto it =
          std::find_if(topics_.begin(), topics_.end(), [&](const BagTopic& t) {
            return t.topic == name;
          });
      if (it == topics_.end()) {
        std::string list;
        for (const BagTopic& t : topics_)
          list += (list.empty() ? "" : ", ") + Ros1Printable(t.topic);
        throw FormatError(path_ + ": no topic '" + name +
                          "' in the bag (its topics: " +
                          (list.empty() ? "none" : list) + ")");
      }
      selected_[static_cast<size_t>(it - topics_.begin())] = true;
    }
  }

  void LoadChunk(uint64_t pos) {
    const Ros1FileRecord record = file_.ReadRecord(pos);
    Ros1ExpectOp(record.header, kRos1OpChunk, "a chunk");
    compressed_.resize(record.data_size);
    file_.Read(record.data_pos, compressed_.size(), compressed_.data());
    Ros1DecompressChunk(record.header.String("compression"),
                        compressed_,
                        record.header.UInt32("size"),
                        &chunk_);
    chunk_offset_ = 0;
  }

  bool NextInChunks(BagMessage* message) {
    for (;;) {
      while (chunk_offset_ < chunk_.size()) {
        const Ros1BufferRecord record =
            Ros1ReadBufferRecord(chunk_.data(), chunk_.size(), chunk_offset_);
        chunk_offset_ = record.end;
        const uint8_t op = record.header.Op();
        if (op == kRos1OpConnection) continue;
        if (op != kRos1OpMessageData) {
          throw FormatError("unexpected op " + std::to_string(op) +
                            " inside a chunk");
        }
        const uint32_t id = record.header.UInt32("conn");
        const auto topic = topic_of_connection_.find(id);
        if (topic == topic_of_connection_.end()) {
          throw FormatError("message on connection " + std::to_string(id) +
                            ", which no connection record declares");
        }
        if (!selected_[topic->second]) continue;
        message->topic_index = topic->second;
        message->log_time_ns = record.header.TimeNs("time");
        message->data.assign(record.data, record.data + record.data_size);
        return true;
      }
      if (next_chunk_ == chunks_.size()) {
        chunk_.clear();
        chunk_offset_ = 0;
        return false;
      }
      LoadChunk(chunks_[next_chunk_++]);
    }
  }

  std::string path_;
  Ros1File file_;
  uint64_t first_record_ = 0;
  std::map<uint32_t, Ros1Connection> connections_;
  std::map<uint32_t, size_t> topic_of_connection_;
  std::vector<BagTopic> topics_;
  std::vector<bool> selected_;
  std::vector<uint64_t> chunks_;  // positions, in file order
  size_t next_chunk_ = 0;
  std::vector<uint8_t> compressed_;
  std::vector<uint8_t> chunk_;
  size_t chunk_offset_ = 0;
};

}  // namespace

bool LooksLikeRos1Bag(const std::string& path) {
  std::ifstream stream(path, std::ios::binary);
  char magic[kRos1MagicSize] = {};
  stream.read(magic, kRos1MagicSize);
  return stream && std::memcmp(magic, kRos1Magic, kRos1MagicSize) == 0;
}

std::unique_ptr<BagReader> OpenRos1Bag(const std::string& path,
                                       const std::vector<std::string>& topics) {
  return std::make_unique<Ros1BagReader>(path, topics);
}

}  // namespace odomcal::bag
