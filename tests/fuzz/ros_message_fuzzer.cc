// Fuzzes the ROS message decoders (adapters/bag/ros_messages.h) on bytes in
// memory. The first input byte chooses the decoder (low nibble modulo 5:
// Image, CompressedImage, CameraInfo, Odometry, JointState) and the wire
// format (bit 4: CDR, else ROS 1); the rest is the serialized message.
//
// Expected outcome for malformed input: FormatError. Anything else (a crash,
// a sanitizer report, std::bad_alloc from an unchecked count, any other
// exception) escapes and is a finding.
#include "odomcal/adapters/bag/ros_messages.h"
#include "odomcal/adapters/format_error.h"

#include <cstddef>
#include <cstdint>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  using odomcal::bag::MessageEncoding;
  const MessageEncoding encoding =
      (data[0] & 0x10) != 0 ? MessageEncoding::kCdr : MessageEncoding::kRos1;
  const std::vector<uint8_t> bytes(data + 1, data + size);
  try {
    switch ((data[0] & 0x0f) % 5) {
      case 0:
        odomcal::bag::DecodeImage(encoding, bytes);
        break;
      case 1:
        odomcal::bag::DecodeCompressedImage(encoding, bytes);
        break;
      case 2:
        odomcal::bag::DecodeCameraInfo(encoding, bytes);
        break;
      case 3:
        odomcal::bag::DecodeOdometry(encoding, bytes);
        break;
      default:
        odomcal::bag::DecodeJointState(encoding, bytes);
        break;
    }
  } catch (const odomcal::FormatError&) {
  }
  return 0;
}
