// The ROS 1 bag reader against bags written by Debian's python3-rosbag
// (tests/fixtures/bags/make_ros1_bags.py, run by the ctest fixture
// BagFixtures.Ros1), whose expected.json holds the values given to rosbag.
#include "odomcal/adapters/bag/ros1_bag_reader.h"

#include "odomcal/adapters/bag/ros_messages.h"
#include "odomcal/adapters/format_error.h"

#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

namespace odomcal::bag {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

fs::path FixturePath(const std::string& name) {
  return fs::path(ODOMCAL_ROS1_FIXTURE_DIR) / name;
}

const json& Expected() {
  static const json expected = [] {
    std::ifstream in(FixturePath("expected.json"));
    return json::parse(in);
  }();
  return expected;
}

std::vector<uint8_t> ReadBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

// A folder of its own for the corrupted copies of one test process; in
// memory where /dev/shm exists (thousands of copies are written).
fs::path ScratchRoot() {
  std::error_code ignored;
  return fs::is_directory("/dev/shm", ignored) ? fs::path("/dev/shm")
                                               : fs::temp_directory_path();
}

class ScratchFiles {
 public:
  ScratchFiles()
      : dir_(ScratchRoot() /
             ("odomcal_bag_ros1_" + std::to_string(::getpid()))) {
    fs::create_directories(dir_);
  }
  ~ScratchFiles() {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }
  std::string Write(const std::string& name,
                    const std::vector<uint8_t>& bytes) const {
    const fs::path path = dir_ / name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
    return path.string();
  }

 private:
  fs::path dir_;
};

struct ReadMessage {
  std::string topic;
  std::string type;
  BagMessage message;
};

std::vector<ReadMessage> ReadAll(BagReader& reader) {
  std::vector<ReadMessage> out;
  BagMessage message;
  while (reader.Next(&message)) {
    const BagTopic& topic = reader.Topics().at(message.topic_index);
    out.push_back({topic.topic, topic.type, message});
  }
  return out;
}

// Opens and drains the bag; returns the FormatError's text, or "" when the
// bag read cleanly (other exceptions escape and fail the test).
std::string ReadError(const std::string& path, size_t* messages = nullptr) {
  try {
    auto reader = OpenRos1Bag(path, {});
    const size_t count = ReadAll(*reader).size();
    if (messages != nullptr) *messages = count;
    return "";
  } catch (const FormatError& e) {
    return e.what();
  }
}

bool StartsWith(const std::string& text, const std::string& prefix) {
  return text.compare(0, prefix.size(), prefix) == 0;
}

std::string Hex(const std::vector<uint8_t>& bytes) {
  static const char digits[] = "0123456789abcdef";
  std::string out;
  for (const uint8_t b : bytes) {
    out += digits[b >> 4];
    out += digits[b & 15];
  }
  return out;
}

template <typename Array>
void ExpectDoubles(const Array& got,
                   const json& want,
                   const std::string& what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  for (size_t i = 0; i < got.size(); ++i) {
    EXPECT_NEAR(got[i], want[i].get<double>(), 1e-12)
        << what << "[" << i << "]";
  }
}

void ExpectFields(const ReadMessage& read, const json& want) {
  const std::vector<uint8_t>& bytes = read.message.data;
  auto expect_header = [&](const RosHeader& header) {
    EXPECT_EQ(header.stamp_ns, want["stamp_ns"].get<int64_t>());
    EXPECT_EQ(header.frame_id, want["frame_id"].get<std::string>());
  };
  if (read.type == "sensor_msgs/Image") {
    const ImageMessage m = DecodeImage(MessageEncoding::kRos1, bytes);
    expect_header(m.header);
    EXPECT_EQ(m.height, want["height"].get<uint32_t>());
    EXPECT_EQ(m.width, want["width"].get<uint32_t>());
    EXPECT_EQ(m.encoding, want["encoding"].get<std::string>());
    EXPECT_EQ(m.is_bigendian, want["is_bigendian"].get<bool>());
    EXPECT_EQ(m.step, want["step"].get<uint32_t>());
    EXPECT_EQ(Hex(m.data), want["data"].get<std::string>());
  } else if (read.type == "sensor_msgs/CompressedImage") {
    const CompressedImageMessage m =
        DecodeCompressedImage(MessageEncoding::kRos1, bytes);
    expect_header(m.header);
    EXPECT_EQ(m.format, want["format"].get<std::string>());
    EXPECT_EQ(Hex(m.data), want["data"].get<std::string>());
  } else if (read.type == "sensor_msgs/CameraInfo") {
    const CameraInfoMessage m = DecodeCameraInfo(MessageEncoding::kRos1, bytes);
    expect_header(m.header);
    EXPECT_EQ(m.height, want["height"].get<uint32_t>());
    EXPECT_EQ(m.width, want["width"].get<uint32_t>());
    EXPECT_EQ(m.distortion_model, want["distortion_model"].get<std::string>());
    ExpectDoubles(m.d, want["d"], "D");
    ExpectDoubles(m.k, want["k"], "K");
    ExpectDoubles(m.r, want["r"], "R");
    ExpectDoubles(m.p, want["p"], "P");
    EXPECT_EQ(m.binning_x, want["binning_x"].get<uint32_t>());
    EXPECT_EQ(m.binning_y, want["binning_y"].get<uint32_t>());
  } else if (read.type == "nav_msgs/Odometry") {
    const OdometryMessage m = DecodeOdometry(MessageEncoding::kRos1, bytes);
    expect_header(m.header);
    EXPECT_EQ(m.child_frame_id, want["child_frame_id"].get<std::string>());
    ExpectDoubles(m.position, want["position"], "position");
    ExpectDoubles(m.orientation, want["orientation"], "orientation");
    ExpectDoubles(
        m.pose_covariance, want["pose_covariance"], "pose covariance");
  } else if (read.type == "sensor_msgs/JointState") {
    const JointStateMessage m = DecodeJointState(MessageEncoding::kRos1, bytes);
    expect_header(m.header);
    EXPECT_EQ(m.name, want["name"].get<std::vector<std::string>>());
    ExpectDoubles(m.position, want["position"], "position");
    ExpectDoubles(m.velocity, want["velocity"], "velocity");
    ExpectDoubles(m.effort, want["effort"], "effort");
  } else {
    ADD_FAILURE() << "unexpected type " << read.type;
  }
}

class Ros1BagFixture : public ::testing::TestWithParam<std::string> {
 protected:
  std::string Path() const { return FixturePath(GetParam()).string(); }
  const json& Want() const { return Expected().at(GetParam()); }
};

TEST_P(Ros1BagFixture, TopicsHaveTheWritersCountsAndTimes) {
  const auto reader = OpenRos1Bag(Path(), {});
  EXPECT_EQ(reader->Path(), Path());
  const json& topics = Want()["topics"];
  ASSERT_EQ(reader->Topics().size(), topics.size());
  for (const BagTopic& topic : reader->Topics()) {
    SCOPED_TRACE(topic.topic);
    ASSERT_TRUE(topics.contains(topic.topic));
    const json& want = topics[topic.topic];
    EXPECT_EQ(topic.type, want["type"].get<std::string>());
    EXPECT_EQ(topic.encoding, MessageEncoding::kRos1);
    EXPECT_EQ(topic.message_count, want["count"].get<int64_t>());
    EXPECT_EQ(topic.first_log_time_ns, want["first_ns"].get<int64_t>());
    EXPECT_EQ(topic.last_log_time_ns, want["last_ns"].get<int64_t>());
  }
}

TEST_P(Ros1BagFixture, StreamsEveryMessageInWriteOrderWithItsValues) {
  const auto reader = OpenRos1Bag(Path(), {});
  const std::vector<ReadMessage> read = ReadAll(*reader);
  const json& want = Want()["messages"];
  ASSERT_EQ(read.size(), want.size());
  for (size_t i = 0; i < read.size(); ++i) {
    SCOPED_TRACE("message " + std::to_string(i) + " on " + read[i].topic);
    EXPECT_EQ(read[i].topic, want[i]["topic"].get<std::string>());
    EXPECT_EQ(read[i].message.log_time_ns,
              want[i]["log_time_ns"].get<int64_t>());
    ExpectFields(read[i], want[i]["fields"]);
  }
  BagMessage after_end;
  EXPECT_FALSE(reader->Next(&after_end));
}

TEST_P(Ros1BagFixture, SelectedTopicsOnly) {
  const std::vector<std::string> selected = {"/odom", "/joint_states"};
  const auto reader = OpenRos1Bag(Path(), selected);
  EXPECT_EQ(reader->Topics().size(),
            Want()["topics"].size());  // still all topics
  const std::vector<ReadMessage> read = ReadAll(*reader);
  std::vector<std::pair<std::string, int64_t>> want;
  for (const json& m : Want()["messages"]) {
    const std::string topic = m["topic"].get<std::string>();
    if (topic == "/odom" || topic == "/joint_states") {
      want.emplace_back(topic, m["log_time_ns"].get<int64_t>());
    }
  }
  ASSERT_EQ(read.size(), want.size());
  for (size_t i = 0; i < read.size(); ++i) {
    EXPECT_EQ(read[i].topic, want[i].first);
    EXPECT_EQ(read[i].message.log_time_ns, want[i].second);
  }
}

TEST_P(Ros1BagFixture, UnknownTopicIsNamedWithTheBagsTopics) {
  try {
    OpenRos1Bag(Path(), {"/odom", "/no_such_topic"});
    FAIL() << "no FormatError";
  } catch (const FormatError& e) {
    const std::string text = e.what();
    EXPECT_TRUE(StartsWith(text, Path() + ": ")) << text;
    EXPECT_NE(text.find("'/no_such_topic'"), std::string::npos) << text;
    EXPECT_NE(text.find("/camera/image_raw, "), std::string::npos) << text;
    EXPECT_EQ(text.find('\n'), std::string::npos) << text;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Bags,
    Ros1BagFixture,
    ::testing::Values("plain.bag", "bz2.bag", "lz4.bag", "unindexed.bag"),
    [](const auto& info) {
      return info.param.substr(0, info.param.find('.'));
    });

TEST(Ros1Bag, RecognisedByContent) {
  EXPECT_TRUE(LooksLikeRos1Bag(FixturePath("lz4.bag").string()));
  EXPECT_FALSE(LooksLikeRos1Bag(FixturePath("expected.json").string()));
  EXPECT_FALSE(LooksLikeRos1Bag(FixturePath("no_such.bag").string()));
}

TEST(Ros1Bag, UnindexedBagReadsOnlyItsCompleteChunks) {
  // The writer knows how many messages reached complete chunks; the open
  // chunk's are lost, as with `rosbag reindex`.
  const auto reader = OpenRos1Bag(FixturePath("unindexed.bag").string(), {});
  const size_t written = Expected()["unindexed.bag"]["messages"].size();
  EXPECT_GT(written, 100u);
  EXPECT_EQ(ReadAll(*reader).size(), written);
}

// Every error names the bag first and is one line.
void ExpectBagError(const std::string& error,
                    const std::string& path,
                    const std::string& part) {
  EXPECT_TRUE(StartsWith(error, path + ": ")) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  EXPECT_NE(error.find(part), std::string::npos)
      << "'" << part << "' not in: " << error;
}

TEST(Ros1Bag, TruncatedFixtureIsAFormatError) {
  const std::string path = FixturePath("truncated.bag").string();
  ExpectBagError(ReadError(path), path, "");
}

TEST(Ros1Bag, MissingFileAndOtherFormatsAreFormatErrors) {
  const ScratchFiles scratch;
  const std::string missing = FixturePath("no_such.bag").string();
  ExpectBagError(ReadError(missing), missing, "cannot open");
  const std::string folder = FixturePath("").string();
  ExpectBagError(ReadError(folder), folder, "is a folder");
  const std::string empty = scratch.Write("empty.bag", {});
  ExpectBagError(ReadError(empty), empty, "not a ROS bag");
  const std::string text = "#ROSBAG V1.2\nmore text here";
  const std::string old =
      scratch.Write("old.bag", std::vector<uint8_t>(text.begin(), text.end()));
  ExpectBagError(ReadError(old), old, "format 1.2 is not supported");
}

// Cuts each bag at many offsets: a closed bag always reports the damage;
// an unclosed one may read its whole chunks before the cut.
TEST(Ros1Bag, TruncationAnywhereIsAFormatErrorOrAShorterUnindexedBag) {
  const ScratchFiles scratch;
  for (const std::string name :
       {"plain.bag", "bz2.bag", "lz4.bag", "unindexed.bag"}) {
    const std::vector<uint8_t> bytes = ReadBytes(FixturePath(name));
    const size_t all = Expected()[name]["messages"].size();
    ASSERT_GT(bytes.size(), 5000u);
    std::vector<size_t> cuts;
    // Every byte of the magic and the bag header's lengths, a sample of its
    // padding, densely over the first chunk (at byte 4117), then sparser.
    for (size_t cut = 0; cut < 64; ++cut) cuts.push_back(cut);
    for (size_t cut = 64; cut < 4100; cut += 97) cuts.push_back(cut);
    for (size_t cut = 4100; cut < 4600; cut += 3) cuts.push_back(cut);
    for (size_t cut = 4600; cut < bytes.size(); cut += 331) {
      cuts.push_back(cut);
    }
    cuts.push_back(bytes.size() - 1);
    for (const size_t cut : cuts) {
      SCOPED_TRACE(name + " cut at " + std::to_string(cut));
      const std::string path = scratch.Write(
          "cut.bag",
          std::vector<uint8_t>(bytes.begin(),
                               bytes.begin() + static_cast<long>(cut)));
      size_t messages = 0;
      const std::string error = ReadError(path, &messages);
      if (name == "unindexed.bag" && error.empty()) {
        EXPECT_LE(messages, all);
      } else {
        ExpectBagError(error, path, "");
      }
    }
  }
}

size_t Find(const std::vector<uint8_t>& bytes,
            const std::string& needle,
            size_t from = 0) {
  const auto it = std::search(bytes.begin() + static_cast<long>(from),
                              bytes.end(),
                              needle.begin(),
                              needle.end());
  return it == bytes.end() ? std::string::npos
                           : static_cast<size_t>(it - bytes.begin());
}

TEST(Ros1Bag, UnknownCompressionIsNamed) {
  const ScratchFiles scratch;
  std::vector<uint8_t> bytes = ReadBytes(FixturePath("bz2.bag"));
  const size_t at = Find(bytes, "compression=bz2");
  ASSERT_NE(at, std::string::npos);
  std::copy_n("zip", 3, bytes.begin() + static_cast<long>(at + 12));
  const std::string path = scratch.Write("zip.bag", bytes);
  ExpectBagError(ReadError(path), path, "unknown compression 'zip'");
}

TEST(Ros1Bag, DecompressedSizeMismatchIsNamed) {
  const ScratchFiles scratch;
  for (const std::string name : {"bz2.bag", "lz4.bag", "plain.bag"}) {
    std::vector<uint8_t> bytes = ReadBytes(FixturePath(name));
    const size_t at = Find(bytes, "size=", Find(bytes, "compression="));
    ASSERT_NE(at, std::string::npos);
    bytes[at + 5] ^= 0x01;  // the size's lowest byte
    const std::string path = scratch.Write("size.bag", bytes);
    ExpectBagError(ReadError(path),
                   path,
                   name == "plain.bag" ? "size of" : "decompress to");
  }
}

TEST(Ros1Bag, UnknownConnectionAndUnknownOpAreNamed) {
  const ScratchFiles scratch;
  const std::vector<uint8_t> bytes = ReadBytes(FixturePath("plain.bag"));
  const std::string message_op("op=\x02", 4);
  const size_t op = Find(bytes, message_op);
  ASSERT_NE(op, std::string::npos);
  const size_t conn = Find(bytes, "conn=", op);
  ASSERT_LT(conn, op + 16);

  std::vector<uint8_t> unknown_conn = bytes;
  unknown_conn[conn + 5] = 0x55;
  const std::string conn_path = scratch.Write("conn.bag", unknown_conn);
  ExpectBagError(ReadError(conn_path), conn_path, "connection 85");

  std::vector<uint8_t> bad_op = bytes;
  bad_op[op + 3] = 0x09;
  const std::string op_path = scratch.Write("op.bag", bad_op);
  ExpectBagError(ReadError(op_path), op_path, "op 9");
}

TEST(Ros1Bag, LengthsPastTheEndAreFormatErrors) {
  const ScratchFiles scratch;
  const std::vector<uint8_t> bytes = ReadBytes(FixturePath("plain.bag"));
  // The first chunk's header length, then a header field length inside it.
  const size_t chunk = Find(bytes, std::string("op=\x05", 4));
  ASSERT_NE(chunk, std::string::npos);
  for (const size_t at : {chunk - 8, chunk - 4}) {
    std::vector<uint8_t> bad = bytes;
    bad[at + 3] = 0x7f;
    const std::string path = scratch.Write("length.bag", bad);
    ExpectBagError(ReadError(path), path, "runs past");
  }
}

// Random byte changes all over each bag: only FormatErrors that name the
// bag, or a clean read; never a crash or another exception.
TEST(Ros1Bag, CorruptedBytesGiveFormatErrorsNamingTheBag) {
  const ScratchFiles scratch;
  std::mt19937 random(20261128);
  for (const std::string name :
       {"plain.bag", "bz2.bag", "lz4.bag", "unindexed.bag"}) {
    const std::vector<uint8_t> bytes = ReadBytes(FixturePath(name));
    std::uniform_int_distribution<size_t> offset(0, bytes.size() - 1);
    std::uniform_int_distribution<int> value(0, 255);
    int errors = 0;
    for (int trial = 0; trial < 150; ++trial) {
      std::vector<uint8_t> bad = bytes;
      // Mostly in the first 5 KB (bag header, first chunks), some anywhere.
      const size_t at = trial % 2 == 0 ? offset(random) % 5000 : offset(random);
      for (int k = 0; k < 3; ++k)
        bad[std::min(bad.size() - 1, at + 4 * k)] =
            static_cast<uint8_t>(value(random));
      const std::string path = scratch.Write("flip.bag", bad);
      const std::string error = ReadError(path);
      if (!error.empty()) {
        ++errors;
        EXPECT_TRUE(StartsWith(error, path + ": ")) << error;
        EXPECT_EQ(error.find('\n'), std::string::npos) << error;
      }
    }
    EXPECT_GT(errors, 0) << name;
  }
}

}  // namespace
}  // namespace odomcal::bag
