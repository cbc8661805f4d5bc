// The field sequences of the messages odomcal reads, in ROS definition
// order; RosWireReader hides the two wire formats.
#include "odomcal/adapters/bag/ros_messages.h"

#include "odomcal/adapters/bag/ros_wire_reader.h"

namespace odomcal::bag {

ImageMessage DecodeImage(MessageEncoding encoding,
                         const std::vector<uint8_t>& bytes) {
  RosWireReader in(encoding, bytes, "sensor_msgs/Image");
  ImageMessage m;
  m.header = in.Header();
  m.height = in.UInt32();
  m.width = in.UInt32();
  m.encoding = in.String();
  m.is_bigendian = in.Bool();
  m.step = in.UInt32();
  m.data = in.UInt8Sequence();
  in.ExpectEnd();
  return m;
}

CompressedImageMessage DecodeCompressedImage(
    MessageEncoding encoding, const std::vector<uint8_t>& bytes) {
  RosWireReader in(encoding, bytes, "sensor_msgs/CompressedImage");
  CompressedImageMessage m;
  m.header = in.Header();
  m.format = in.String();
  m.data = in.UInt8Sequence();
  in.ExpectEnd();
  return m;
}

CameraInfoMessage DecodeCameraInfo(MessageEncoding encoding,
                                   const std::vector<uint8_t>& bytes) {
  RosWireReader in(encoding, bytes, "sensor_msgs/CameraInfo");
  CameraInfoMessage m;
  m.header = in.Header();
  m.height = in.UInt32();
  m.width = in.UInt32();
  m.distortion_model = in.String();
  m.d = in.Float64Sequence();
  m.k = in.Float64Array<9>();
  m.r = in.Float64Array<9>();
  m.p = in.Float64Array<12>();
  m.binning_x = in.UInt32();
  m.binning_y = in.UInt32();
  m.roi.x_offset = in.UInt32();
  m.roi.y_offset = in.UInt32();
  m.roi.height = in.UInt32();
  m.roi.width = in.UInt32();
  in.Bool();  // roi.do_rectify
  in.ExpectEnd();
  return m;
}

OdometryMessage DecodeOdometry(MessageEncoding encoding,
                               const std::vector<uint8_t>& bytes) {
  RosWireReader in(encoding, bytes, "nav_msgs/Odometry");
  OdometryMessage m;
  m.header = in.Header();
  m.child_frame_id = in.String();
  m.position = in.Float64Array<3>();
  m.orientation = in.Float64Array<4>();
  m.pose_covariance = in.Float64Array<36>();
  // twist (TwistWithCovariance): linear, angular, covariance; not used.
  in.Float64Array<3 + 3 + 36>();
  in.ExpectEnd();
  return m;
}

JointStateMessage DecodeJointState(MessageEncoding encoding,
                                   const std::vector<uint8_t>& bytes) {
  RosWireReader in(encoding, bytes, "sensor_msgs/JointState");
  JointStateMessage m;
  m.header = in.Header();
  m.name = in.StringSequence();
  m.position = in.Float64Sequence();
  m.velocity = in.Float64Sequence();
  m.effort = in.Float64Sequence();
  in.ExpectEnd();
  return m;
}

}  // namespace odomcal::bag
