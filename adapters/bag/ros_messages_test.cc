// The message decoders on hand-laid bytes. CDR buffers are written field by
// field with the padding spelled out (Pad), so the alignment rules are the
// test's own statement, not the decoder's: every primitive aligned to its
// size counted from the byte after the 4-byte encapsulation header; strings
// carry their NUL in the length; an empty sequence has no padding after its
// count. ROS 1 values against rosbag's bytes are in ros1_bag_reader_test.cc.
#include "odomcal/adapters/bag/ros_messages.h"

#include "odomcal/adapters/format_error.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace odomcal::bag {
namespace {

// Appends primitives without any alignment of its own.
class Bytes {
 public:
  explicit Bytes(bool big_endian = false) : big_endian_(big_endian) {}
  Bytes& Raw(std::initializer_list<uint8_t> bytes) {
    data_.insert(data_.end(), bytes.begin(), bytes.end());
    return *this;
  }
  Bytes& Pad(size_t count) {
    data_.insert(
        data_.end(), count, 0xAA);  // not zero: padding is skipped, not read
    return *this;
  }
  Bytes& U32(uint32_t v) { return Int(v, 4); }
  Bytes& F64(double v) {
    uint64_t bits = 0;
    std::memcpy(&bits, &v, sizeof v);
    return Int(bits, 8);
  }
  Bytes& Chars(const std::string& s) {
    data_.insert(data_.end(), s.begin(), s.end());
    return *this;
  }
  size_t Offset() const { return data_.size(); }
  std::vector<uint8_t> Data() const { return data_; }

 private:
  Bytes& Int(uint64_t v, int size) {
    for (int i = 0; i < size; ++i) {
      const int shift = 8 * (big_endian_ ? size - 1 - i : i);
      data_.push_back(static_cast<uint8_t>(v >> shift));
    }
    return *this;
  }
  bool big_endian_;
  std::vector<uint8_t> data_;
};

// nav_msgs/Odometry in CDR; offsets in comments count from the byte after
// the encapsulation header.
std::vector<uint8_t> CdrOdometry(bool big_endian) {
  Bytes b(big_endian);
  b.Raw({0x00, static_cast<uint8_t>(big_endian ? 0x00 : 0x01), 0x00, 0x00});
  b.U32(static_cast<uint32_t>(-2));        // 0: sec = -2 (signed in ROS 2)
  b.U32(250000000);                        // 4: nanosec
  b.U32(5).Chars(std::string("odom", 5));  // 8: frame_id "odom\0", ends at 17
  b.Pad(3);                                // 17 -> 20
  b.U32(10).Chars(
      std::string("base_link", 10));  // 20: child_frame_id, ends at 34
  b.Pad(6);                           // 34 -> 40: float64 aligned to 8
  for (const double v : {1.5, -2.25, 0.125}) b.F64(v);
  for (const double v : {0.0, 0.0, 0.6, 0.8}) b.F64(v);
  for (int i = 0; i < 36; ++i) b.F64(i * 0.5);
  for (int i = 0; i < 42; ++i)
    b.F64(-1.0);  // twist: linear, angular, covariance
  return b.Data();
}

TEST(BagRosMessages, CdrOdometryLittleAndBigEndian) {
  for (const bool big_endian : {false, true}) {
    SCOPED_TRACE(big_endian ? "big-endian" : "little-endian");
    const OdometryMessage m =
        DecodeOdometry(MessageEncoding::kCdr, CdrOdometry(big_endian));
    EXPECT_EQ(m.header.stamp_ns, -2000000000LL + 250000000LL);
    EXPECT_EQ(m.header.frame_id, "odom");
    EXPECT_EQ(m.child_frame_id, "base_link");
    EXPECT_EQ(m.position, (std::array<double, 3>{1.5, -2.25, 0.125}));
    EXPECT_EQ(m.orientation, (std::array<double, 4>{0.0, 0.0, 0.6, 0.8}));
    EXPECT_EQ(m.pose_covariance[35], 17.5);
  }
}

TEST(BagRosMessages, CdrJointStateEmptySequenceHasNoPadding) {
  Bytes b;
  b.Raw({0x00, 0x01, 0x00, 0x00});
  b.U32(7).U32(8);       // 0: stamp
  b.U32(1).Raw({0x00});  // 8: frame_id "" (just the NUL), ends at 13
  b.Pad(3);              // 13 -> 16
  b.U32(2);              // 16: name count
  b.U32(5).Chars(std::string("left", 5));   // 20: ends at 29
  b.Pad(3);                                 // 29 -> 32
  b.U32(6).Chars(std::string("right", 6));  // 32: ends at 42
  b.Pad(2);                                 // 42 -> 44
  b.U32(0);               // 44: position, empty: no padding after
  b.U32(2);               // 48: velocity count
  b.Pad(4);               // 52 -> 56
  b.F64(1.25).F64(-3.5);  // 56
  b.U32(1);               // 72: effort count
  b.Pad(4);               // 76 -> 80
  b.F64(9.0);
  const JointStateMessage m = DecodeJointState(MessageEncoding::kCdr, b.Data());
  EXPECT_EQ(m.header.stamp_ns, 7000000008LL);
  EXPECT_EQ(m.header.frame_id, "");
  EXPECT_EQ(m.name, (std::vector<std::string>{"left", "right"}));
  EXPECT_TRUE(m.position.empty());
  EXPECT_EQ(m.velocity, (std::vector<double>{1.25, -3.5}));
  EXPECT_EQ(m.effort, (std::vector<double>{9.0}));
}

std::vector<uint8_t> CdrCameraInfo() {
  Bytes b;
  b.Raw({0x00, 0x01, 0x00, 0x00});
  b.U32(100).U32(0);                              // 0: stamp
  b.U32(4).Chars(std::string("cam", 4));          // 8: ends at 16
  b.U32(480).U32(640);                            // 16: height, width
  b.U32(10).Chars(std::string("plumb_bob", 10));  // 24: ends at 38
  b.Pad(2);                                       // 38 -> 40
  b.U32(5);                                       // 40: d count
  b.Pad(4);                                       // 44 -> 48
  for (int i = 0; i < 5; ++i) b.F64(0.1 * i);     // 48
  for (int i = 0; i < 30; ++i) b.F64(i);          // k, r, p
  b.U32(2).U32(3);                                // binning
  b.U32(1).U32(2).U32(3).U32(4).Raw({0x01});      // roi
  return b.Data();
}

TEST(BagRosMessages, CdrCameraInfo) {
  const CameraInfoMessage m =
      DecodeCameraInfo(MessageEncoding::kCdr, CdrCameraInfo());
  EXPECT_EQ(m.header.stamp_ns, 100000000000LL);
  EXPECT_EQ(m.header.frame_id, "cam");
  EXPECT_EQ(m.height, 480u);
  EXPECT_EQ(m.width, 640u);
  EXPECT_EQ(m.distortion_model, "plumb_bob");
  ASSERT_EQ(m.d.size(), 5u);
  EXPECT_EQ(m.d[4], 0.1 * 4);
  EXPECT_EQ(m.k[0], 0.0);
  EXPECT_EQ(m.r[0], 9.0);
  EXPECT_EQ(m.p[11], 29.0);
  EXPECT_EQ(m.binning_x, 2u);
  EXPECT_EQ(m.binning_y, 3u);
}

TEST(BagRosMessages, CdrImageAndCompressedImage) {
  Bytes image;
  image.Raw({0x00, 0x01, 0x00, 0x00});
  image.U32(1).U32(2);
  image.U32(4).Chars(std::string("cam", 4));    // 8: ends at 16
  image.U32(2).U32(3);                          // 16: height, width
  image.U32(6).Chars(std::string("mono8", 6));  // 24: ends at 34
  image.Raw({0x00});                            // 34: is_bigendian
  image.Pad(1);                                 // 35 -> 36
  image.U32(3);                                 // 36: step
  image.U32(6).Raw({1, 2, 3, 4, 5, 6});         // 40: data
  const ImageMessage m = DecodeImage(MessageEncoding::kCdr, image.Data());
  EXPECT_EQ(m.encoding, "mono8");
  EXPECT_FALSE(m.is_bigendian);
  EXPECT_EQ(m.step, 3u);
  EXPECT_EQ(m.data, (std::vector<uint8_t>{1, 2, 3, 4, 5, 6}));

  Bytes compressed;
  compressed.Raw({0x00, 0x01, 0x00, 0x00});
  compressed.U32(1).U32(2);
  compressed.U32(1).Raw({0x00});  // 8: frame_id "", ends at 13
  compressed.Pad(3);
  compressed.U32(5).Chars(std::string("jpeg", 5));  // 16: ends at 25
  compressed.Pad(3);
  compressed.U32(2).Raw({0xff, 0xd8});  // 28
  const CompressedImageMessage c =
      DecodeCompressedImage(MessageEncoding::kCdr, compressed.Data());
  EXPECT_EQ(c.format, "jpeg");
  EXPECT_EQ(c.data, (std::vector<uint8_t>{0xff, 0xd8}));
}

TEST(BagRosMessages, Ros1HeaderHasSeqAndUnsignedSeconds) {
  Bytes b;
  b.U32(42).U32(4000000000u).U32(5);  // seq, sec beyond int32, nsec
  b.U32(4).Chars("base");             // frame_id, no NUL in ROS 1
  b.U32(1).Chars("p").U32(3).Raw({7, 8, 9});
  const CompressedImageMessage m =
      DecodeCompressedImage(MessageEncoding::kRos1, b.Data());
  EXPECT_EQ(m.header.stamp_ns, 4000000000LL * 1000000000LL + 5);
  EXPECT_EQ(m.header.frame_id, "base");
  EXPECT_EQ(m.format, "p");
  EXPECT_EQ(m.data, (std::vector<uint8_t>{7, 8, 9}));
}

void ExpectDecodeError(const std::vector<uint8_t>& bytes,
                       MessageEncoding encoding,
                       const std::string& part) {
  try {
    DecodeOdometry(encoding, bytes);
    ADD_FAILURE() << "no FormatError for " << bytes.size() << " bytes";
  } catch (const FormatError& e) {
    const std::string text = e.what();
    EXPECT_EQ(text.rfind("nav_msgs/Odometry: ", 0), 0u) << text;
    EXPECT_NE(text.find(part), std::string::npos) << text;
    EXPECT_EQ(text.find('\n'), std::string::npos) << text;
  }
}

TEST(BagRosMessages, EveryShorterOrLongerBufferIsAFormatError) {
  const std::vector<uint8_t> whole = CdrOdometry(false);
  for (size_t size = 0; size < whole.size(); ++size) {
    ExpectDecodeError(
        std::vector<uint8_t>(whole.begin(),
                             whole.begin() + static_cast<long>(size)),
        MessageEncoding::kCdr,
        "");
  }
  std::vector<uint8_t> longer = whole;
  longer.push_back(0);
  ExpectDecodeError(longer, MessageEncoding::kCdr, "left over");
  // The same bytes read as ROS 1 do not line up either.
  ExpectDecodeError(whole, MessageEncoding::kRos1, "");
}

TEST(BagRosMessages, CdrEncapsulationStringsAndCountsAreChecked) {
  std::vector<uint8_t> parameter_list = CdrOdometry(false);
  parameter_list[1] = 0x03;  // PL_CDR_LE
  ExpectDecodeError(parameter_list, MessageEncoding::kCdr, "not plain CDR");

  std::vector<uint8_t> no_nul = CdrOdometry(false);
  no_nul[4 + 16] = 'x';  // frame_id's NUL
  ExpectDecodeError(no_nul, MessageEncoding::kCdr, "NUL");

  std::vector<uint8_t> long_string = CdrOdometry(false);
  long_string[4 + 8 + 3] = 0x40;  // frame_id length 0x40000005
  ExpectDecodeError(long_string, MessageEncoding::kCdr, "longer than");

  // A JointState claiming 2^31 names must fail on the count, not allocate.
  Bytes b;
  b.Raw({0x00, 0x01, 0x00, 0x00})
      .U32(0)
      .U32(0)
      .U32(1)
      .Raw({0})
      .Pad(3)
      .U32(0x80000000u);
  EXPECT_THROW(DecodeJointState(MessageEncoding::kCdr, b.Data()), FormatError);
}

}  // namespace
}  // namespace odomcal::bag
