// Fuzzes the ROS 1 bag reader: the input is written to a scratch file
// input.bag, opened with OpenRos1Bag (all topics), and read to the end; each
// message of a type odomcal decodes goes through its decoder, as the
// importer would.
//
// Expected outcome for malformed input: FormatError (from the reader or a
// decoder). Anything else (a crash, a sanitizer report, std::bad_alloc from
// an unchecked length, any other exception) escapes and is a finding.
#include "odomcal/adapters/bag/ros1_bag_reader.h"
#include "odomcal/adapters/bag/ros_messages.h"
#include "odomcal/adapters/format_error.h"

#include "scratch_dir.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace {

void DecodeAs(const std::string& type,
              const odomcal::bag::BagMessage& message) {
  using odomcal::bag::MessageEncoding;
  try {
    if (type == "sensor_msgs/Image") {
      odomcal::bag::DecodeImage(MessageEncoding::kRos1, message.data);
    } else if (type == "sensor_msgs/CompressedImage") {
      odomcal::bag::DecodeCompressedImage(MessageEncoding::kRos1, message.data);
    } else if (type == "sensor_msgs/CameraInfo") {
      odomcal::bag::DecodeCameraInfo(MessageEncoding::kRos1, message.data);
    } else if (type == "nav_msgs/Odometry") {
      odomcal::bag::DecodeOdometry(MessageEncoding::kRos1, message.data);
    } else if (type == "sensor_msgs/JointState") {
      odomcal::bag::DecodeJointState(MessageEncoding::kRos1, message.data);
    }
  } catch (const odomcal::FormatError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const odomcal::ScratchDir scratch;
  const std::string path =
      scratch.Write("input.bag", odomcal::AsBytes(data, size));
  try {
    const auto reader = odomcal::bag::OpenRos1Bag(path, {});
    odomcal::bag::BagMessage message;
    while (reader->Next(&message)) {
      DecodeAs(reader->Topics().at(message.topic_index).type, message);
    }
  } catch (const odomcal::FormatError&) {
  }
  return 0;
}
