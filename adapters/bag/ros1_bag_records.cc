#include "odomcal/adapters/bag/ros1_bag_records.h"

#include "odomcal/adapters/format_error.h"

#include <algorithm>

namespace odomcal::bag {

Ros1RecordHeader Ros1RecordHeader::Parse(const uint8_t* data, size_t size) {
  Ros1RecordHeader header;
  size_t pos = 0;
  while (pos < size) {
    if (size - pos < 4) {
      throw FormatError("header field length cut off (" +
                        std::to_string(size - pos) + " bytes left)");
    }
    const uint32_t length = Ros1LoadU32(data + pos);
    pos += 4;
    if (length > size - pos) {
      throw FormatError("header field of " + std::to_string(length) +
                        " bytes runs past the header's end (" +
                        std::to_string(size - pos) + " bytes left)");
    }
    const char* field = reinterpret_cast<const char*>(data + pos);
    const char* equals = std::find(field, field + length, '=');
    if (equals == field + length) {
      throw FormatError("header field without '='");
    }
    header.fields_.emplace_back(std::string(field, equals),
                                std::string(equals + 1, field + length));
    pos += length;
  }
  return header;
}

bool Ros1RecordHeader::Has(const std::string& name) const {
  return std::any_of(fields_.begin(), fields_.end(), [&](const auto& f) {
    return f.first == name;
  });
}

const std::string& Ros1RecordHeader::Value(const std::string& name,
                                           size_t expected_size) const {
  const auto it = std::find_if(fields_.begin(),
                               fields_.end(),
                               [&](const auto& f) { return f.first == name; });
  if (it == fields_.end()) {
    throw FormatError("record header has no field '" + name + "'");
  }
  if (expected_size != 0 && it->second.size() != expected_size) {
    throw FormatError("header field '" + name + "' has " +
                      std::to_string(it->second.size()) + " bytes, expected " +
                      std::to_string(expected_size));
  }
  return it->second;
}

uint8_t Ros1RecordHeader::Op() const {
  return static_cast<uint8_t>(Value("op", 1)[0]);
}

uint32_t Ros1RecordHeader::UInt32(const std::string& name) const {
  return Ros1LoadU32(reinterpret_cast<const uint8_t*>(Value(name, 4).data()));
}

uint64_t Ros1RecordHeader::UInt64(const std::string& name) const {
  return Ros1LoadU64(reinterpret_cast<const uint8_t*>(Value(name, 8).data()));
}

int64_t Ros1RecordHeader::TimeNs(const std::string& name) const {
  return Ros1TimeNs(reinterpret_cast<const uint8_t*>(Value(name, 8).data()));
}

const std::string& Ros1RecordHeader::String(const std::string& name) const {
  return Value(name, 0);
}

Ros1BufferRecord Ros1ReadBufferRecord(const uint8_t* bytes,
                                      size_t size,
                                      size_t offset) {
  Ros1BufferRecord record;
  size_t pos = offset;
  if (pos > size || size - pos < 4) {
    throw FormatError("record header length cut off");
  }
  const uint32_t header_size = Ros1LoadU32(bytes + pos);
  pos += 4;
  if (header_size > size - pos) {
    throw FormatError("record header of " + std::to_string(header_size) +
                      " bytes runs past the end (" +
                      std::to_string(size - pos) + " bytes left)");
  }
  record.header = Ros1RecordHeader::Parse(bytes + pos, header_size);
  pos += header_size;
  if (size - pos < 4) {
    throw FormatError("record data length cut off");
  }
  const uint32_t data_size = Ros1LoadU32(bytes + pos);
  pos += 4;
  if (data_size > size - pos) {
    throw FormatError("record data of " + std::to_string(data_size) +
                      " bytes runs past the end (" +
                      std::to_string(size - pos) + " bytes left)");
  }
  record.data = bytes + pos;
  record.data_size = data_size;
  record.end = pos + data_size;
  return record;
}

}  // namespace odomcal::bag
