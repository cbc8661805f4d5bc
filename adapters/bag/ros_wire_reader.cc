#include "odomcal/adapters/bag/ros_wire_reader.h"

#include "odomcal/adapters/format_error.h"

#include <cstring>

namespace odomcal::bag {

RosWireReader::RosWireReader(MessageEncoding encoding,
                             const std::vector<uint8_t>& bytes,
                             const char* type)
    : bytes_(bytes), type_(type), cdr_(encoding == MessageEncoding::kCdr) {
  if (!cdr_) return;
  if (bytes_.size() < 4)
    Fail("CDR data of " + std::to_string(bytes_.size()) +
         " bytes, shorter than the encapsulation header");
  if (bytes_[0] != 0x00 || bytes_[1] > 0x01) {
    Fail("CDR encapsulation " + std::to_string(bytes_[0]) + "," +
         std::to_string(bytes_[1]) +
         " is not plain CDR (0,0 big-endian or 0,1 little-endian)");
  }
  big_endian_ = bytes_[1] == 0x00;
  origin_ = 4;
  pos_ = 4;
}

void RosWireReader::Fail(const std::string& problem) const {
  throw FormatError(std::string(type_) + ": " + problem);
}

void RosWireReader::Align(size_t size) {
  if (!cdr_) return;
  const size_t misalignment = (pos_ - origin_) % size;
  if (misalignment == 0) return;
  Take(size - misalignment, "alignment padding");
}

const uint8_t* RosWireReader::Take(size_t count, const char* what) {
  if (count > bytes_.size() - pos_) {
    Fail(std::string(what) + " of " + std::to_string(count) +
         " bytes at byte " + std::to_string(pos_) + " runs past the end (" +
         std::to_string(bytes_.size()) + " bytes)");
  }
  const uint8_t* p = bytes_.data() + pos_;
  pos_ += count;
  return p;
}

uint32_t RosWireReader::LoadU32(const uint8_t* p) const {
  if (big_endian_) {
    return (static_cast<uint32_t>(p[0]) << 24) |
           (static_cast<uint32_t>(p[1]) << 16) |
           (static_cast<uint32_t>(p[2]) << 8) | static_cast<uint32_t>(p[3]);
  }
  return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) |
         (static_cast<uint32_t>(p[2]) << 16) |
         (static_cast<uint32_t>(p[3]) << 24);
}

bool RosWireReader::Bool() { return *Take(1, "bool") != 0; }

uint32_t RosWireReader::UInt32() {
  Align(4);
  return LoadU32(Take(4, "uint32"));
}

double RosWireReader::Float64() {
  Align(8);
  const uint8_t* p = Take(8, "float64");
  const uint64_t low = LoadU32(big_endian_ ? p + 4 : p);
  const uint64_t high = LoadU32(big_endian_ ? p : p + 4);
  const uint64_t bits = low | (high << 32);
  double value = 0;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

uint32_t RosWireReader::Count(size_t min_element_bytes, const char* what) {
  const uint32_t count = UInt32();
  const size_t left = bytes_.size() - pos_;
  if (min_element_bytes != 0 && count > left / min_element_bytes) {
    Fail(std::string(what) + " of " + std::to_string(count) +
         " elements at byte " + std::to_string(pos_ - 4) +
         " is longer than the " + std::to_string(left) + " bytes left");
  }
  return count;
}

std::string RosWireReader::String() {
  const uint32_t length = Count(1, "string");
  const char* p = reinterpret_cast<const char*>(Take(length, "string"));
  if (!cdr_ || length == 0) return std::string(p, length);
  // CDR counts the terminating NUL.
  if (p[length - 1] != '\0')
    Fail("CDR string at byte " + std::to_string(pos_ - length) +
         " does not end with NUL");
  return std::string(p, length - 1);
}

std::vector<uint8_t> RosWireReader::UInt8Sequence() {
  const uint32_t count = Count(1, "uint8 sequence");
  const uint8_t* p = Take(count, "uint8 sequence");
  return std::vector<uint8_t>(p, p + count);
}

std::vector<double> RosWireReader::Float64Sequence() {
  const uint32_t count = Count(8, "float64 sequence");
  std::vector<double> values(count);
  for (double& v : values) v = Float64();
  return values;
}

std::vector<std::string> RosWireReader::StringSequence() {
  // Each string holds at least its 4-byte length.
  const uint32_t count = Count(4, "string sequence");
  std::vector<std::string> values;
  values.reserve(count);
  for (uint32_t i = 0; i < count; ++i) values.push_back(String());
  return values;
}

int64_t RosWireReader::TimeNs() {
  const uint32_t sec_bits = UInt32();
  const uint32_t nsec = UInt32();
  // ROS 1 seconds are unsigned, ROS 2 (builtin_interfaces/Time) signed.
  const int64_t sec = cdr_
                          ? static_cast<int64_t>(static_cast<int32_t>(sec_bits))
                          : static_cast<int64_t>(sec_bits);
  return sec * 1000000000 + static_cast<int64_t>(nsec);
}

RosHeader RosWireReader::Header() {
  if (!cdr_) UInt32();  // seq
  RosHeader header;
  header.stamp_ns = TimeNs();
  header.frame_id = String();
  return header;
}

void RosWireReader::ExpectEnd() const {
  if (pos_ != bytes_.size()) {
    Fail(std::to_string(bytes_.size() - pos_) +
         " bytes left over after the message (" +
         std::to_string(bytes_.size()) + " bytes)");
  }
}

}  // namespace odomcal::bag
