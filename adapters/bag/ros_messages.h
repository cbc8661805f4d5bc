// The ROS messages odomcal reads from bags, decoded from either wire format
// (bag_reader.h's MessageEncoding). Field names follow the ROS definitions;
// ROS 1 and ROS 2 lay these messages out identically except for the
// header's sequence number (ROS 1 only) and CDR's alignment and strings.
//
// Conventions at this boundary: stamps are integer nanoseconds (header.stamp,
// the capture time); quaternions are ROS's (x, y, z, w) Hamilton; pixel
// coordinates (CameraInfo's K and P) are ROS/OpenCV's, where the top-left
// pixel's centre is (0, 0).
//
// Each Decode* throws FormatError("<type>: <problem>") on bytes that do not
// hold the message (too short, a length past the end, trailing bytes); the
// caller prefixes the bag path and topic.
#pragma once

#include "odomcal/adapters/bag/bag_reader.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace odomcal::bag {

struct RosHeader {
  int64_t stamp_ns = 0;
  std::string frame_id;
};

// sensor_msgs/Image
struct ImageMessage {
  RosHeader header;
  uint32_t height = 0;
  uint32_t width = 0;
  std::string encoding;  // "mono8", "rgb8", "bayer_rggb8", ...
  bool is_bigendian = false;
  uint32_t step = 0;  // bytes per row
  std::vector<uint8_t> data;
};

// sensor_msgs/CompressedImage
struct CompressedImageMessage {
  RosHeader header;
  std::string format;  // "jpeg", "png", "rgb8; jpeg compressed bgr8", ...
  std::vector<uint8_t> data;
};

// sensor_msgs/RegionOfInterest (do_rectify dropped)
struct RegionOfInterest {
  uint32_t x_offset = 0;
  uint32_t y_offset = 0;
  uint32_t height = 0;
  uint32_t width = 0;
};

// sensor_msgs/CameraInfo (ROS 1 names D, K, R, P; ROS 2 d, k, r, p)
struct CameraInfoMessage {
  RosHeader header;
  uint32_t height = 0;
  uint32_t width = 0;
  std::string distortion_model;  // "plumb_bob", "equidistant", ...
  std::vector<double> d;
  std::array<double, 9> k{};   // row-major 3x3
  std::array<double, 9> r{};   // row-major 3x3
  std::array<double, 12> p{};  // row-major 3x4
  uint32_t binning_x = 0;
  uint32_t binning_y = 0;
  RegionOfInterest roi;  // all zero: the full image
};

// nav_msgs/Odometry (pose part; the twist is parsed and dropped)
struct OdometryMessage {
  RosHeader header;
  std::string child_frame_id;
  std::array<double, 3> position{};     // x, y, z
  std::array<double, 4> orientation{};  // x, y, z, w (ROS order)
  std::array<double, 36> pose_covariance{};
};

// sensor_msgs/JointState
struct JointStateMessage {
  RosHeader header;
  std::vector<std::string> name;
  std::vector<double> position;
  std::vector<double> velocity;
  std::vector<double> effort;
};

ImageMessage DecodeImage(MessageEncoding encoding,
                         const std::vector<uint8_t>& bytes);
CompressedImageMessage DecodeCompressedImage(MessageEncoding encoding,
                                             const std::vector<uint8_t>& bytes);
CameraInfoMessage DecodeCameraInfo(MessageEncoding encoding,
                                   const std::vector<uint8_t>& bytes);
OdometryMessage DecodeOdometry(MessageEncoding encoding,
                               const std::vector<uint8_t>& bytes);
JointStateMessage DecodeJointState(MessageEncoding encoding,
                                   const std::vector<uint8_t>& bytes);

}  // namespace odomcal::bag
