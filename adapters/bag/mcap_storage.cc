// MCAP storage (mcap_storage.h). Messages stream through the data section in
// file order, one chunk in memory at a time; the summary (when the footer
// points at one) gives the channels and, through the message indexes after
// each chunk, every topic's count and time span without decompressing.
#include "odomcal/adapters/bag/mcap_storage.h"

#include "odomcal/adapters/bag/mcap_records.h"
#include "odomcal/adapters/format_error.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace odomcal::bag::internal {
namespace {

namespace fs = std::filesystem;

// The Footer record: opcode, length and its three fields.
constexpr uint64_t kMcapFooterRecord = kMcapRecordPrefix + kMcapFooterContent;

uint64_t McapLe64(const uint8_t* bytes) {
  uint64_t value = 0;
  for (int i = 7; i >= 0; --i) value = (value << 8) | bytes[i];
  return value;
}

// Reads byte ranges of the file; a short read throws FormatError.
class McapFile {
 public:
  explicit McapFile(const std::string& path) : path_(path) {
    std::error_code error;
    if (path.empty() || !fs::is_regular_file(path, error)) {
      Fail(fs::exists(path, error)
               ? "cannot open the MCAP file: not a regular file"
               : "cannot open the MCAP file: no such file");
    }
    stream_.open(path, std::ios::binary);
    const uintmax_t size = fs::file_size(path, error);
    if (!stream_ || error) Fail("cannot open the MCAP file for reading");
    size_ = static_cast<uint64_t>(size);
  }

  uint64_t size() const { return size_; }
  const std::string& path() const { return path_; }

  void Read(uint64_t offset, uint64_t size, uint8_t* out) {
    CheckRange(offset, size);
    stream_.clear();
    stream_.seekg(static_cast<std::streamoff>(offset));
    stream_.read(reinterpret_cast<char*>(out),
                 static_cast<std::streamsize>(size));
    if (!stream_) Fail("cannot read at byte " + std::to_string(offset));
  }

  void Read(uint64_t offset, uint64_t size, std::vector<uint8_t>* out) {
    CheckRange(offset, size);
    out->resize(static_cast<size_t>(size));
    Read(offset, size, out->data());
  }

  [[noreturn]] void Fail(const std::string& what) const {
    throw FormatError(path_ + ": " + what);
  }

 private:
  // Every length read from the file is checked here before it is allocated.
  void CheckRange(uint64_t offset, uint64_t size) const {
    if (offset > size_ || size > size_ - offset) {
      Fail("reading " + std::to_string(size) + " bytes at byte " +
           std::to_string(offset) + " past the end of the file (" +
           std::to_string(size_) + " bytes)");
    }
  }

  std::string path_;
  std::ifstream stream_;
  uint64_t size_ = 0;
};

const char* McapRecordName(uint8_t opcode) {
  switch (opcode) {
    case kMcapSchema:
      return "schema";
    case kMcapChannel:
      return "channel";
    case kMcapMessage:
      return "message";
    case kMcapChunkIndex:
      return "chunk index";
    case kMcapStatistics:
      return "statistics";
    case kMcapMessageIndex:
      return "message index";
    default:
      return "record";
  }
}

// One Schema, Channel or Message record of the data section, from the top
// level or from inside a chunk.
struct McapItem {
  uint8_t opcode = 0;
  const uint8_t* content = nullptr;
  size_t size = 0;
  const std::string* context = nullptr;
};

class McapRos2Storage final : public Ros2Storage {
 public:
  explicit McapRos2Storage(const std::string& path) : file_(path) {
    ReadStart();
    const bool has_footer = ReadFooter();
    bool indexed = false;
    if (has_footer && footer_.summary_start != 0) {
      ReadSummary();
      indexed = CountFromIndexes();
    }
    if (!indexed) {
      // No usable summary: the data section itself, up to its last complete
      // record when the file has no footer.
      tolerate_truncation_ = !has_footer;
      schemas_.clear();
      channels_.clear();
      chunk_channels_.clear();
      spans_.clear();
      ScanCounts();
    }
    BuildTopics();
    Select(std::vector<bool>(topics_.size(), true));
  }

  const std::vector<Ros2StorageTopic>& Topics() const override {
    return topics_;
  }

  void Select(const std::vector<bool>& selected) override {
    selected_channels_.clear();
    for (const auto& [channel, topic] : topic_of_channel_) {
      if (topic < selected.size() && selected[topic]) {
        selected_channels_.push_back(channel);
      }
    }
  }

  bool Next(BagMessage* message) override {
    McapItem item;
    while (NextItem(&item)) {
      if (item.opcode != kMcapMessage) continue;
      McapCursor cursor(item.content, item.size, *item.context);
      const McapMessageView view = ParseMcapMessage(&cursor);
      const auto topic = topic_of_channel_.find(view.channel_id);
      if (topic == topic_of_channel_.end()) {
        cursor.Fail("message on channel " + std::to_string(view.channel_id) +
                    ", which no channel record defines");
      }
      if (!IsSelected(view.channel_id)) continue;
      message->topic_index = topic->second;
      message->log_time_ns = LogTime(view.log_time, cursor);
      message->data.assign(view.data, view.data + view.size);
      return true;
    }
    return false;
  }

 private:
  [[noreturn]] void Fail(const std::string& what) const { file_.Fail(what); }

  static int64_t LogTime(uint64_t time, const McapCursor& cursor) {
    if (time > static_cast<uint64_t>(std::numeric_limits<int64_t>::max())) {
      cursor.Fail("log time " + std::to_string(time) + " past the year 2262");
    }
    return static_cast<int64_t>(time);
  }

  bool IsSelected(uint16_t channel) const {
    return std::find(selected_channels_.begin(),
                     selected_channels_.end(),
                     channel) != selected_channels_.end();
  }

  // Magic, then a Header record.
  void ReadStart() {
    uint8_t start[sizeof(kMcapMagic) + 1] = {};
    if (file_.size() < sizeof(start)) {
      Fail("not an MCAP file: " + std::to_string(file_.size()) +
           " bytes, shorter than the magic and a header");
    }
    file_.Read(0, sizeof(start), start);
    if (std::memcmp(start, kMcapMagic, sizeof(kMcapMagic)) != 0) {
      Fail("not an MCAP file (no MCAP magic at its start)");
    }
    if (start[sizeof(kMcapMagic)] != kMcapHeader) {
      Fail("no header record after the magic (opcode " +
           std::to_string(start[sizeof(kMcapMagic)]) + ")");
    }
    position_ = sizeof(kMcapMagic);
  }

  // The Footer and closing magic; false when the file does not end with
  // them (a recording that was stopped before it closed the file).
  bool ReadFooter() {
    const uint64_t tail = kMcapFooterRecord + sizeof(kMcapMagic);
    if (file_.size() < sizeof(kMcapMagic) + tail) return false;
    footer_offset_ = file_.size() - tail;
    uint8_t bytes[kMcapFooterRecord + sizeof(kMcapMagic)] = {};
    file_.Read(footer_offset_, tail, bytes);
    if (std::memcmp(
            bytes + kMcapFooterRecord, kMcapMagic, sizeof(kMcapMagic)) != 0 ||
        bytes[0] != kMcapFooter || McapLe64(bytes + 1) != kMcapFooterContent) {
      return false;
    }
    const std::string context =
        file_.path() + ": footer at byte " + std::to_string(footer_offset_);
    McapCursor cursor(bytes + kMcapRecordPrefix, kMcapFooterContent, context);
    footer_ = ParseMcapFooter(&cursor);
    const uint64_t header_end = sizeof(kMcapMagic) + kMcapRecordPrefix;
    if (footer_.summary_start != 0 &&
        (footer_.summary_start < header_end ||
         footer_.summary_start > footer_offset_)) {
      cursor.Fail("summary start " + std::to_string(footer_.summary_start) +
                  " outside the file");
    }
    if (footer_.summary_offset_start != 0 &&
        (footer_.summary_offset_start < footer_.summary_start ||
         footer_.summary_offset_start > footer_offset_)) {
      cursor.Fail("summary offset start " +
                  std::to_string(footer_.summary_offset_start) +
                  " outside the summary");
    }
    data_end_ =
        footer_.summary_start != 0 ? footer_.summary_start : footer_offset_;
    return true;
  }

  void CheckSummaryCrc() {
    // From the summary's start through the footer's summary_offset_start.
    const uint64_t end = footer_offset_ + kMcapRecordPrefix + 16;
    std::vector<uint8_t> block;
    uint32_t crc = 0;
    for (uint64_t at = footer_.summary_start; at < end;) {
      const uint64_t size = std::min<uint64_t>(end - at, 1 << 20);
      file_.Read(at, size, &block);
      crc = McapCrc32(crc, block.data(), block.size());
      at += size;
    }
    if (crc != footer_.summary_crc) {
      Fail("summary CRC mismatch (summary " + std::to_string(crc) +
           ", footer says " + std::to_string(footer_.summary_crc) + ")");
    }
  }

  // Schemas, channels, statistics and chunk indexes of the summary section.
  void ReadSummary() {
    if (footer_.summary_crc != 0) CheckSummaryCrc();
    const uint64_t end = footer_.summary_offset_start != 0
                             ? footer_.summary_offset_start
                             : footer_offset_;
    std::vector<uint8_t> content;
    for (uint64_t at = footer_.summary_start; at < end;) {
      uint8_t prefix[kMcapRecordPrefix];
      if (end - at < kMcapRecordPrefix) {
        Fail("summary record at byte " + std::to_string(at) +
             " cut by the summary's end");
      }
      file_.Read(at, kMcapRecordPrefix, prefix);
      const uint64_t size = McapLe64(prefix + 1);
      if (size > end - at - kMcapRecordPrefix) {
        Fail("summary record at byte " + std::to_string(at) + " of " +
             std::to_string(size) + " bytes runs past the summary's end");
      }
      const uint8_t opcode = prefix[0];
      const std::string context = file_.path() + ": summary " +
                                  McapRecordName(opcode) + " at byte " +
                                  std::to_string(at);
      if (opcode == kMcapSchema || opcode == kMcapChannel ||
          opcode == kMcapChunkIndex || opcode == kMcapStatistics) {
        file_.Read(at + kMcapRecordPrefix, size, &content);
        McapCursor cursor(content.data(), content.size(), context);
        if (opcode == kMcapSchema) {
          AddSchema(ParseMcapSchema(&cursor), cursor);
        } else if (opcode == kMcapChannel) {
          AddChannel(ParseMcapChannel(&cursor), cursor);
        } else if (opcode == kMcapChunkIndex) {
          chunk_indexes_.push_back(ParseMcapChunkIndex(&cursor));
        } else {
          statistics_ = ParseMcapStatistics(&cursor);
          has_statistics_ = true;
        }
      }
      at += kMcapRecordPrefix + size;
    }
  }

  void AddSchema(McapSchema schema, const McapCursor& cursor) {
    if (schema.id == 0) return;  // the spec's "no schema"; ignored
    const auto [it, added] = schemas_.emplace(schema.id, schema);
    if (!added && (it->second.name != schema.name ||
                   it->second.encoding != schema.encoding)) {
      cursor.Fail("schema " + std::to_string(schema.id) +
                  " defined twice, differently");
    }
  }

  void AddChannel(McapChannel channel, const McapCursor& cursor) {
    const auto [it, added] = channels_.emplace(channel.id, channel);
    if (!added && (it->second.topic != channel.topic ||
                   it->second.schema_id != channel.schema_id ||
                   it->second.message_encoding != channel.message_encoding)) {
      cursor.Fail("channel " + std::to_string(channel.id) +
                  " defined twice, differently");
    }
  }

  // Counts and time spans from the Message Index records that follow each
  // chunk; false when the file lacks them (the caller then scans).
  bool CountFromIndexes() {
    if (chunk_indexes_.empty()) return false;  // messages outside chunks
    std::vector<uint8_t> content;
    uint64_t total = 0;
    for (const McapChunkIndex& chunk : chunk_indexes_) {
      if (chunk.message_index_offsets.empty()) return false;
      std::vector<uint16_t>& channels =
          chunk_channels_[chunk.chunk_start_offset];
      for (const auto& [channel, offset] : chunk.message_index_offsets) {
        const std::string context =
            file_.path() + ": message index at byte " + std::to_string(offset);
        uint8_t prefix[kMcapRecordPrefix];
        if (offset < sizeof(kMcapMagic) || offset > data_end_ ||
            data_end_ - offset < kMcapRecordPrefix) {
          Fail("message index offset " + std::to_string(offset) +
               " outside the data section");
        }
        file_.Read(offset, kMcapRecordPrefix, prefix);
        const uint64_t size = McapLe64(prefix + 1);
        if (prefix[0] != kMcapMessageIndex ||
            size > data_end_ - offset - kMcapRecordPrefix) {
          Fail("message index offset " + std::to_string(offset) +
               " does not point at a message index record");
        }
        file_.Read(offset + kMcapRecordPrefix, size, &content);
        McapCursor cursor(content.data(), content.size(), context);
        const McapIndexSpan span = ParseMcapMessageIndex(&cursor);
        if (span.channel_id != channel) {
          cursor.Fail("indexes channel " + std::to_string(span.channel_id) +
                      ", the chunk index says " + std::to_string(channel));
        }
        if (channels_.count(channel) == 0) return false;
        Count(channel,
              span.count,
              span.first_log_time,
              span.last_log_time,
              cursor);
        channels.push_back(channel);
        total += span.count;
      }
    }
    // Messages outside chunks are in the statistics but not in any index.
    return !has_statistics_ || statistics_.message_count == total;
  }

  void Count(uint16_t channel,
             uint64_t count,
             uint64_t first,
             uint64_t last,
             const McapCursor& cursor) {
    if (count == 0) return;
    Span& span = spans_[channel];
    const int64_t first_ns = LogTime(first, cursor);
    const int64_t last_ns = LogTime(last, cursor);
    if (span.count == 0 || first_ns < span.first) span.first = first_ns;
    if (span.count == 0 || last_ns > span.last) span.last = last_ns;
    span.count += static_cast<int64_t>(count);
  }

  // One pass over the data section for the channels, counts and spans.
  void ScanCounts() {
    McapItem item;
    while (NextItem(&item)) {
      McapCursor cursor(item.content, item.size, *item.context);
      if (item.opcode == kMcapSchema) {
        AddSchema(ParseMcapSchema(&cursor), cursor);
      } else if (item.opcode == kMcapChannel) {
        AddChannel(ParseMcapChannel(&cursor), cursor);
      } else {
        const McapMessageView view = ParseMcapMessage(&cursor);
        if (channels_.count(view.channel_id) == 0) {
          cursor.Fail("message on channel " + std::to_string(view.channel_id) +
                      " before any channel record defines it");
        }
        Count(view.channel_id, 1, view.log_time, view.log_time, cursor);
      }
    }
    position_ = sizeof(kMcapMagic);
    done_ = false;
  }

  // Topics in channel-id order; channels of one topic become one topic.
  void BuildTopics() {
    for (const auto& [id, channel] : channels_) {
      Ros2StorageTopic topic;
      topic.topic.topic = channel.topic;
      topic.topic.encoding = MessageEncoding::kCdr;
      const auto schema = schemas_.find(channel.schema_id);
      if (channel.schema_id != 0 && schema == schemas_.end()) {
        Fail("channel " + std::to_string(id) + " (" +
             Ros2Quoted(channel.topic) + ") refers to schema " +
             std::to_string(channel.schema_id) +
             ", which the file does not define");
      }
      if (channel.message_encoding != "cdr") {
        topic.refusal = "message encoding " +
                        Ros2Quoted(channel.message_encoding) +
                        ", not 'cdr' (ROS 2)";
      } else if (channel.schema_id == 0) {
        topic.refusal = "no schema, so no message type";
      } else if (schema->second.encoding != "ros2msg" &&
                 schema->second.encoding != "ros2idl" &&
                 schema->second.encoding != "unknown") {
        // "unknown": rosbag2's mark for a type whose definition it lacked.
        topic.refusal = "schema encoding " +
                        Ros2Quoted(schema->second.encoding) +
                        ", not 'ros2msg' or 'ros2idl'";
      }
      if (schema != schemas_.end()) {
        topic.topic.type = NormaliseRos2Type(schema->second.name);
      }
      const auto span = spans_.find(id);
      if (span != spans_.end()) {
        topic.topic.message_count = span->second.count;
        topic.topic.first_log_time_ns = span->second.first;
        topic.topic.last_log_time_ns = span->second.last;
      }
      Merge(id, std::move(topic));
    }
  }

  void Merge(uint16_t channel, Ros2StorageTopic topic) {
    for (size_t i = 0; i < topics_.size(); ++i) {
      BagTopic& known = topics_[i].topic;
      if (known.topic != topic.topic.topic) continue;
      if (known.type != topic.topic.type ||
          topics_[i].refusal != topic.refusal) {
        Fail("topic " + Ros2Quoted(known.topic) +
             " has channels of different types or encodings");
      }
      AddMessagesOf(topic.topic, &known);
      topic_of_channel_[channel] = i;
      return;
    }
    topic_of_channel_[channel] = topics_.size();
    topics_.push_back(std::move(topic));
  }

  // Whether a chunk can be skipped unread: the index lists its channels and
  // none is selected.
  bool SkipChunk(uint64_t offset) const {
    const auto chunk = chunk_channels_.find(offset);
    if (chunk == chunk_channels_.end()) return false;
    for (const uint16_t channel : chunk->second) {
      if (IsSelected(channel)) return false;
    }
    return true;
  }

  // The next Schema, Channel or Message record; false at the data
  // section's end (its Data End record, the summary, or, in a file without
  // a footer, the last complete record).
  bool NextItem(McapItem* item) {
    while (true) {
      if (chunk_position_ < chunk_.size()) {
        const size_t left = chunk_.size() - chunk_position_;
        const uint8_t* record = chunk_.data() + chunk_position_;
        if (left < kMcapRecordPrefix ||
            McapLe64(record + 1) > left - kMcapRecordPrefix) {
          throw FormatError(chunk_context_ + ": record at offset " +
                            std::to_string(chunk_position_) +
                            " runs past the chunk's end");
        }
        const size_t size = static_cast<size_t>(McapLe64(record + 1));
        chunk_position_ += kMcapRecordPrefix + size;
        if (record[0] == kMcapSchema || record[0] == kMcapChannel ||
            record[0] == kMcapMessage) {
          *item = {
              record[0], record + kMcapRecordPrefix, size, &chunk_context_};
          return true;
        }
        continue;  // other and unknown records: skipped by their length
      }
      if (done_) return false;
      const uint64_t end = tolerate_truncation_ ? file_.size() : data_end_;
      if (position_ >= end) {
        done_ = true;
        return false;
      }
      uint8_t prefix[kMcapRecordPrefix];
      uint64_t size = 0;
      if (end - position_ >= kMcapRecordPrefix) {
        file_.Read(position_, kMcapRecordPrefix, prefix);
        size = McapLe64(prefix + 1);
      }
      if (end - position_ < kMcapRecordPrefix ||
          size > end - position_ - kMcapRecordPrefix) {
        if (tolerate_truncation_) {
          done_ = true;
          return false;
        }
        Fail("record at byte " + std::to_string(position_) +
             " runs past the end of the data section (byte " +
             std::to_string(end) + ")");
      }
      const uint64_t at = position_;
      position_ += kMcapRecordPrefix + size;
      const uint8_t opcode = prefix[0];
      if (opcode == kMcapDataEnd || opcode == kMcapFooter) {
        done_ = true;
        return false;
      }
      if (opcode == kMcapChunk) {
        if (SkipChunk(at)) continue;
        record_context_ =
            file_.path() + ": chunk at byte " + std::to_string(at);
        file_.Read(at + kMcapRecordPrefix, size, &record_);
        McapCursor cursor(record_.data(), record_.size(), record_context_);
        chunk_context_ = record_context_;
        DecompressMcapChunk(ParseMcapChunk(&cursor), chunk_context_, &chunk_);
        chunk_position_ = 0;
      } else if (opcode == kMcapSchema || opcode == kMcapChannel ||
                 opcode == kMcapMessage) {
        record_context_ = file_.path() + ": " + McapRecordName(opcode) +
                          " record at byte " + std::to_string(at);
        file_.Read(at + kMcapRecordPrefix, size, &record_);
        *item = {opcode, record_.data(), record_.size(), &record_context_};
        return true;
      }
      // Header, attachments, metadata, message indexes, unknown: skipped.
    }
  }

  struct Span {
    int64_t count = 0;
    int64_t first = 0;
    int64_t last = 0;
  };

  McapFile file_;
  McapFooter footer_;
  uint64_t footer_offset_ = 0;
  uint64_t data_end_ = 0;
  bool tolerate_truncation_ = false;
  std::map<uint16_t, McapSchema> schemas_;
  std::map<uint16_t, McapChannel> channels_;
  std::vector<McapChunkIndex> chunk_indexes_;
  McapStatistics statistics_;
  bool has_statistics_ = false;
  std::map<uint16_t, Span> spans_;
  // Chunk offset -> its channels, from the index, to skip unselected chunks.
  std::map<uint64_t, std::vector<uint16_t>> chunk_channels_;

  std::vector<Ros2StorageTopic> topics_;
  std::map<uint16_t, size_t> topic_of_channel_;
  std::vector<uint16_t> selected_channels_;

  // Streaming state: the next top-level record, and the open chunk.
  uint64_t position_ = 0;
  bool done_ = false;
  std::vector<uint8_t> record_;
  std::string record_context_;
  std::vector<uint8_t> chunk_;
  size_t chunk_position_ = 0;
  std::string chunk_context_;
};

}  // namespace

std::unique_ptr<Ros2Storage> OpenMcapStorage(const std::string& path) {
  return std::make_unique<McapRos2Storage>(path);
}

bool LooksLikeMcapFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  char head[sizeof(kMcapMagic)] = {};
  if (!file.read(head, sizeof(head))) return false;
  return std::memcmp(head, kMcapMagic, sizeof(kMcapMagic)) == 0;
}

}  // namespace odomcal::bag::internal
