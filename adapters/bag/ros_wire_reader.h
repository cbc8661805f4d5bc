// Reads a serialized ROS message field by field, in either wire format, so
// that each message's field sequence is written once (ros_messages.cc):
//   kRos1: little-endian, packed; string = uint32 length + bytes; sequence =
//          uint32 count + elements; time = uint32 sec + uint32 nsec.
//   kCdr:  a 4-byte encapsulation header (0x00 0x01 CDR little-endian,
//          0x00 0x00 CDR big-endian), then every primitive aligned to its size
//          relative to the byte after that header; string = uint32 length
//          including the terminating NUL, then the bytes and the NUL;
//          sequence = uint32 count + elements; time = int32 sec + uint32
//          nanosec.
// Fixed-size arrays have no count in either format.
//
// Internal to odomcal_bag. Every problem throws FormatError("<type>: ...").
#pragma once

#include "odomcal/adapters/bag/bag_reader.h"
#include "odomcal/adapters/bag/ros_messages.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace odomcal::bag {

class RosWireReader {
 public:
  // `type` ("sensor_msgs/Image") names the message in errors.
  RosWireReader(MessageEncoding encoding,
                const std::vector<uint8_t>& bytes,
                const char* type);

  bool Bool();
  uint32_t UInt32();
  double Float64();
  std::string String();
  std::vector<uint8_t> UInt8Sequence();
  std::vector<double> Float64Sequence();
  std::vector<std::string> StringSequence();
  template <size_t N>
  std::array<double, N> Float64Array() {
    std::array<double, N> values{};
    for (double& v : values) v = Float64();
    return values;
  }
  // std_msgs/Header: ROS 1 has a uint32 seq first (dropped).
  RosHeader Header();
  // Throws when bytes are left over: they hold some other message.
  void ExpectEnd() const;

 private:
  [[noreturn]] void Fail(const std::string& problem) const;
  // Skips CDR padding so that the next `size`-byte primitive is aligned.
  void Align(size_t size);
  const uint8_t* Take(size_t count, const char* what);
  // A sequence count, checked against the bytes left (each element needs at
  // least `min_element_bytes`).
  uint32_t Count(size_t min_element_bytes, const char* what);
  uint32_t LoadU32(const uint8_t* p) const;
  int64_t TimeNs();

  const std::vector<uint8_t>& bytes_;
  const char* type_;
  bool cdr_ = false;
  bool big_endian_ = false;
  size_t origin_ = 0;  // where CDR alignment is measured from
  size_t pos_ = 0;
};

}  // namespace odomcal::bag
