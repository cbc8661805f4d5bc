// The record layer of ROS 1 bags, format 2.0
// (http://wiki.ros.org/Bags/Format/2.0). Every record is, little-endian:
//   uint32 header_len, header, uint32 data_len, data
// and a header is a run of fields, each uint32 field_len then "name=value"
// (the value is raw bytes: integers little-endian, times uint32 sec + uint32
// nsec). Connection records reuse the header layout for their data.
//
// Internal to odomcal_bag. Problems throw FormatError with the bare problem
// ("header field 'op' has 2 bytes, expected 1"); the reader prefixes the path
// and the byte offset.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace odomcal::bag {

constexpr uint8_t kRos1OpMessageData = 0x02;
constexpr uint8_t kRos1OpBagHeader = 0x03;
constexpr uint8_t kRos1OpIndexData = 0x04;
constexpr uint8_t kRos1OpChunk = 0x05;
constexpr uint8_t kRos1OpChunkInfo = 0x06;
constexpr uint8_t kRos1OpConnection = 0x07;

inline uint32_t Ros1LoadU32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) |
         (static_cast<uint32_t>(p[2]) << 16) |
         (static_cast<uint32_t>(p[3]) << 24);
}

inline uint64_t Ros1LoadU64(const uint8_t* p) {
  return static_cast<uint64_t>(Ros1LoadU32(p)) |
         (static_cast<uint64_t>(Ros1LoadU32(p + 4)) << 32);
}

// A ROS 1 time (uint32 sec, uint32 nsec) in integer nanoseconds; the range
// of uint32 seconds fits int64 nanoseconds.
inline int64_t Ros1TimeNs(const uint8_t* p) {
  return static_cast<int64_t>(Ros1LoadU32(p)) * 1000000000 +
         static_cast<int64_t>(Ros1LoadU32(p + 4));
}

// The fields of one record header (or of a connection record's data).
class Ros1RecordHeader {
 public:
  // Parses `size` bytes of fields; throws FormatError when a field length
  // runs past the end or a field has no '='.
  static Ros1RecordHeader Parse(const uint8_t* data, size_t size);

  bool Has(const std::string& name) const;
  // Field "op" (1 byte).
  uint8_t Op() const;
  // Required fields of a fixed size; FormatError when missing or sized wrong.
  uint32_t UInt32(const std::string& name) const;
  uint64_t UInt64(const std::string& name) const;
  int64_t TimeNs(const std::string& name) const;
  const std::string& String(const std::string& name) const;

 private:
  const std::string& Value(const std::string& name, size_t expected_size) const;

  std::vector<std::pair<std::string, std::string>> fields_;
};

// One record inside a buffer that is already in memory (a decompressed
// chunk, or the index read as a whole).
struct Ros1BufferRecord {
  Ros1RecordHeader header;
  const uint8_t* data = nullptr;
  size_t data_size = 0;
  size_t end = 0;  // offset of the next record
};

// Reads the record at `offset` of bytes[0, size); FormatError when a length
// runs past `size`.
Ros1BufferRecord Ros1ReadBufferRecord(const uint8_t* bytes,
                                      size_t size,
                                      size_t offset);

}  // namespace odomcal::bag
