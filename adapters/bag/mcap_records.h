// The MCAP records that mcap_storage.cc reads (https://mcap.dev/spec), parsed
// from one record's content in memory, and chunk decompression; internal:
// not installed.
//
// Every read checks the bytes that remain; a field that does not fit throws
// FormatError("<context>: <what>"), where the context names the file and the
// record ("run.mcap: chunk at byte 4711").
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace odomcal::bag::internal {

inline constexpr uint8_t kMcapMagic[8] = {
    0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
// A record's opcode (1 byte) and content length (uint64).
inline constexpr size_t kMcapRecordPrefix = 9;
// Footer content: summary_start, summary_offset_start, summary_crc.
inline constexpr size_t kMcapFooterContent = 20;

enum McapOpcode : uint8_t {
  kMcapHeader = 0x01,
  kMcapFooter = 0x02,
  kMcapSchema = 0x03,
  kMcapChannel = 0x04,
  kMcapMessage = 0x05,
  kMcapChunk = 0x06,
  kMcapMessageIndex = 0x07,
  kMcapChunkIndex = 0x08,
  kMcapStatistics = 0x0b,
  kMcapDataEnd = 0x0f,
};

// Little-endian fields of one record's content.
class McapCursor {
 public:
  // `context` must outlive the cursor.
  McapCursor(const uint8_t* data, size_t size, const std::string& context)
      : data_(data), size_(size), context_(&context) {}

  uint16_t U16(const char* field);
  uint32_t U32(const char* field);
  uint64_t U64(const char* field);
  // A uint32 length-prefixed string.
  std::string String(const char* field);
  // Skips a uint32 length-prefixed field (Map, Array, Bytes).
  void SkipPrefixed32(const char* field);
  // The rest of the content (a Message's data).
  std::pair<const uint8_t*, size_t> Rest();
  const uint8_t* Take(size_t size, const char* field);

  size_t remaining() const { return size_ - position_; }
  const std::string& context() const { return *context_; }
  [[noreturn]] void Fail(const std::string& what) const;

 private:
  const uint8_t* data_;
  size_t size_;
  size_t position_ = 0;
  const std::string* context_;
};

struct McapSchema {
  uint16_t id = 0;
  std::string name;
  std::string encoding;
};

struct McapChannel {
  uint16_t id = 0;
  uint16_t schema_id = 0;
  std::string topic;
  std::string message_encoding;
};

struct McapMessageView {
  uint16_t channel_id = 0;
  uint64_t log_time = 0;
  const uint8_t* data = nullptr;
  size_t size = 0;
};

struct McapChunkView {
  uint64_t uncompressed_size = 0;
  uint32_t uncompressed_crc = 0;
  std::string compression;
  const uint8_t* records = nullptr;
  size_t records_size = 0;
};

struct McapChunkIndex {
  uint64_t chunk_start_offset = 0;
  uint64_t chunk_length = 0;
  // (channel id, file offset of that channel's Message Index record).
  std::vector<std::pair<uint16_t, uint64_t>> message_index_offsets;
};

struct McapStatistics {
  uint64_t message_count = 0;
  // (channel id, message count); empty when the writer did not count.
  std::vector<std::pair<uint16_t, uint64_t>> channel_message_counts;
};

struct McapFooter {
  uint64_t summary_start = 0;
  uint64_t summary_offset_start = 0;
  uint32_t summary_crc = 0;
};

McapSchema ParseMcapSchema(McapCursor* cursor);
McapChannel ParseMcapChannel(McapCursor* cursor);
McapMessageView ParseMcapMessage(McapCursor* cursor);
McapChunkView ParseMcapChunk(McapCursor* cursor);
McapChunkIndex ParseMcapChunkIndex(McapCursor* cursor);
McapStatistics ParseMcapStatistics(McapCursor* cursor);
McapFooter ParseMcapFooter(McapCursor* cursor);
// A Message Index's entries: the count and the earliest and latest log time.
struct McapIndexSpan {
  uint16_t channel_id = 0;
  uint64_t count = 0;
  uint64_t first_log_time = 0;
  uint64_t last_log_time = 0;
};
McapIndexSpan ParseMcapMessageIndex(McapCursor* cursor);

// The chunk's records, decompressed ("", "zstd", "lz4" frames) into *out
// (resized to uncompressed_size) and checked against uncompressed_crc when
// that is non-zero. Memory grows with the output actually produced, never
// past uncompressed_size, so a forged size cannot make it allocate.
void DecompressMcapChunk(const McapChunkView& chunk,
                         const std::string& context,
                         std::vector<uint8_t>* out);

// One zstd frame that declares its content size (ZSTD_compress writes it;
// rosbag2's compression_mode MESSAGE stores each message so), inflated into
// *out with the bounds of DecompressMcapChunk.
void InflateZstdFrame(const uint8_t* data,
                      size_t size,
                      const std::string& context,
                      std::vector<uint8_t>* out);

// CRC-32 (IEEE, zlib's), continued from `crc` (0 to start).
uint32_t McapCrc32(uint32_t crc, const uint8_t* data, size_t size);

}  // namespace odomcal::bag::internal
