// ROS 2 bag reader on bags written by the reference writers
// (tests/fixtures/bags/make_ros2_bags.mjs: @mcap/core, rosbag2's SQLite
// schema, CDR from @foxglove/rosmsg2-serialization). Every expected value
// comes from that generator's expected.json: the message bytes as the
// serializer wrote them, the order a reader returns them in, the topics.
#include "odomcal/adapters/bag/ros2_bag_reader.h"

#include "odomcal/adapters/format_error.h"

#include <yaml-cpp/yaml.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sqlite3.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace odomcal::bag {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const std::string kFixtures = ODOMCAL_ROS2_BAG_FIXTURES;

struct ExpectedMessage {
  std::string topic;
  int64_t log_time_ns = 0;
  std::vector<uint8_t> bytes;
};

std::vector<uint8_t> FromHex(const std::string& hex) {
  std::vector<uint8_t> bytes;
  for (size_t i = 0; i + 1 < hex.size(); i += 2) {
    bytes.push_back(
        static_cast<uint8_t>(std::stoi(hex.substr(i, 2), nullptr, 16)));
  }
  return bytes;
}

const json& Expected() {
  static const json expected = [] {
    std::ifstream file(kFixtures + "/expected.json");
    return json::parse(file);
  }();
  return expected;
}

const std::vector<ExpectedMessage>& ExpectedMessages() {
  static const std::vector<ExpectedMessage> messages = [] {
    std::vector<ExpectedMessage> all;
    for (const json& m : Expected().at("messages")) {
      all.push_back({m.at("topic").get<std::string>(),
                     std::stoll(m.at("log_time_ns").get<std::string>()),
                     FromHex(m.at("hex").get<std::string>())});
      EXPECT_EQ(all.back().bytes.size(), m.at("size").get<size_t>());
    }
    return all;
  }();
  return messages;
}

// The expected messages of a bag, in the order its reader returns them.
std::vector<ExpectedMessage> ExpectedOrder(const std::string& bag) {
  std::vector<ExpectedMessage> ordered;
  for (const json& index : Expected().at("bags").at(bag).at("order")) {
    ordered.push_back(ExpectedMessages().at(index.get<size_t>()));
  }
  return ordered;
}

std::vector<BagMessage> ReadAll(BagReader* reader) {
  std::vector<BagMessage> messages;
  BagMessage message;
  while (reader->Next(&message)) messages.push_back(message);
  return messages;
}

std::vector<uint8_t> ReadFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file),
          std::istreambuf_iterator<char>()};
}

void WriteFile(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file.write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
}

uint64_t Le64(const std::vector<uint8_t>& bytes, size_t at) {
  uint64_t value = 0;
  for (int i = 7; i >= 0; --i)
    value = (value << 8) | bytes.at(at + static_cast<size_t>(i));
  return value;
}

void PutLe64(std::vector<uint8_t>* bytes, size_t at, uint64_t value) {
  for (size_t i = 0; i < 8; ++i)
    bytes->at(at + i) = static_cast<uint8_t>(value >> (8 * i));
}

// The file offsets of the records of type `opcode` in the data section.
std::vector<size_t> McapRecordOffsets(const std::vector<uint8_t>& bytes,
                                      uint8_t opcode) {
  std::vector<size_t> offsets;
  for (size_t at = 8; at + 9 <= bytes.size();) {
    const uint8_t op = bytes[at];
    if (op == opcode) offsets.push_back(at);
    if (op == 0x0f || op == 0x02) break;  // Data End, Footer
    at += 9 + static_cast<size_t>(Le64(bytes, at + 1));
  }
  return offsets;
}

// A private folder for altered copies of the fixtures.
class ScratchFolder {
 public:
  ScratchFolder() {
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    std::string name =
        std::string(info->test_suite_name()) + "." + info->name();
    std::replace(name.begin(), name.end(), '/', '_');
    path_ =
        (fs::path(kFixtures).parent_path() / "ros2_scratch" / name).string();
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~ScratchFolder() {
    std::error_code error;
    fs::remove_all(path_, error);
  }
  std::string File(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

// Opens and reads the whole bag; on FormatError returns its message.
bool TryReadAll(const std::string& path,
                std::vector<BagMessage>* messages,
                std::string* error) {
  try {
    const auto reader = OpenRos2Bag(path, {});
    *messages = ReadAll(reader.get());
    return true;
  } catch (const FormatError& e) {
    *error = e.what();
    return false;
  }
}

void ExpectOneLineFrom(const std::string& error, const std::string& path) {
  EXPECT_EQ(error.rfind(path, 0), 0u) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
}

// The FormatError of reading `path`; fails the test when there is none.
std::string ReadError(const std::string& path) {
  std::vector<BagMessage> messages;
  std::string error;
  EXPECT_FALSE(TryReadAll(path, &messages, &error))
      << path << " read without error";
  ExpectOneLineFrom(error, path);
  return error;
}

class Ros2BagTest : public testing::TestWithParam<std::string> {};

std::string ParamName(const testing::TestParamInfo<std::string>& info) {
  std::string name = info.param;
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return name;
}

TEST_P(Ros2BagTest, TopicsMatchTheWriter) {
  const std::string path = kFixtures + "/" + GetParam();
  ASSERT_TRUE(LooksLikeRos2Bag(path));
  const auto reader = OpenRos2Bag(path, {});
  EXPECT_EQ(reader->Path(), path);
  const json& expected = Expected().at("bags").at(GetParam()).at("topics");
  ASSERT_EQ(reader->Topics().size(), expected.size());
  for (const BagTopic& topic : reader->Topics()) {
    SCOPED_TRACE(topic.topic);
    ASSERT_TRUE(expected.contains(topic.topic));
    const json& want = expected.at(topic.topic);
    EXPECT_EQ(topic.type, want.at("type").get<std::string>());
    EXPECT_EQ(topic.encoding, MessageEncoding::kCdr);
    EXPECT_EQ(topic.message_count, want.at("count").get<int64_t>());
    EXPECT_EQ(topic.first_log_time_ns,
              std::stoll(want.at("first_log_time_ns").get<std::string>()));
    EXPECT_EQ(topic.last_log_time_ns,
              std::stoll(want.at("last_log_time_ns").get<std::string>()));
  }
}

TEST_P(Ros2BagTest, MessagesAreTheSerializedBytesInStorageOrder) {
  const std::string path = kFixtures + "/" + GetParam();
  const auto reader = OpenRos2Bag(path, {});
  const std::vector<BagMessage> messages = ReadAll(reader.get());
  const std::vector<ExpectedMessage> expected = ExpectedOrder(GetParam());
  ASSERT_EQ(messages.size(), expected.size());
  for (size_t i = 0; i < messages.size(); ++i) {
    SCOPED_TRACE("message " + std::to_string(i));
    ASSERT_LT(messages[i].topic_index, reader->Topics().size());
    EXPECT_EQ(reader->Topics()[messages[i].topic_index].topic,
              expected[i].topic);
    EXPECT_EQ(messages[i].log_time_ns, expected[i].log_time_ns);
    ASSERT_EQ(messages[i].data, expected[i].bytes);
  }
  BagMessage after;
  EXPECT_FALSE(reader->Next(&after));
}

TEST_P(Ros2BagTest, SelectedTopicsOnly) {
  const std::string path = kFixtures + "/" + GetParam();
  const std::vector<std::string> selected = {"/odom", "/camera/camera_info"};
  const auto reader = OpenRos2Bag(path, selected);
  EXPECT_EQ(reader->Topics().size(),
            Expected().at("bags").at(GetParam()).at("topics").size());
  const std::vector<BagMessage> messages = ReadAll(reader.get());
  std::vector<ExpectedMessage> expected;
  for (const ExpectedMessage& m : ExpectedOrder(GetParam())) {
    if (m.topic == selected[0] || m.topic == selected[1]) expected.push_back(m);
  }
  ASSERT_EQ(messages.size(), expected.size());
  for (size_t i = 0; i < messages.size(); ++i) {
    EXPECT_EQ(reader->Topics()[messages[i].topic_index].topic,
              expected[i].topic);
    EXPECT_EQ(messages[i].log_time_ns, expected[i].log_time_ns);
    EXPECT_EQ(messages[i].data, expected[i].bytes);
  }
}

TEST_P(Ros2BagTest, UnknownTopicListsTheBagsTopics) {
  const std::string path = kFixtures + "/" + GetParam();
  try {
    OpenRos2Bag(path, {"/odom", "/no_such_topic"});
    FAIL() << "an unknown topic was accepted";
  } catch (const FormatError& error) {
    const std::string what = error.what();
    ExpectOneLineFrom(what, path);
    EXPECT_NE(what.find("/no_such_topic"), std::string::npos) << what;
    EXPECT_NE(what.find("/joint_states"), std::string::npos) << what;
    EXPECT_NE(what.find("/camera/image_raw/compressed"), std::string::npos)
        << what;
  }
}

INSTANTIATE_TEST_SUITE_P(Fixtures,
                         Ros2BagTest,
                         testing::Values("none.mcap",
                                         "zstd.mcap",
                                         "lz4.mcap",
                                         "unchunked.mcap",
                                         "no_summary.mcap",
                                         "mcap_bag",
                                         "db3_bag",
                                         "db3_bag/db3_bag_0.db3",
                                         "split_bag",
                                         "message_zstd_bag"),
                         ParamName);

// The fixtures exercise what the tests above rely on.
TEST(Ros2BagFixtures, StorageOrderDiffersFromTimeOrder) {
  const std::vector<ExpectedMessage> mcap = ExpectedOrder("zstd.mcap");
  EXPECT_FALSE(std::is_sorted(
      mcap.begin(), mcap.end(), [](const auto& a, const auto& b) {
        return a.log_time_ns < b.log_time_ns;
      }));
  const std::vector<ExpectedMessage> db3 = ExpectedOrder("db3_bag");
  EXPECT_TRUE(
      std::is_sorted(db3.begin(), db3.end(), [](const auto& a, const auto& b) {
        return a.log_time_ns < b.log_time_ns;
      }));
  const std::vector<uint8_t> zstd = ReadFile(kFixtures + "/zstd.mcap");
  EXPECT_GT(McapRecordOffsets(zstd, 0x06).size(), 5u) << "several chunks";
  EXPECT_EQ(Expected().at("bags").at("split_bag").at("files").get<int>(), 2);
}

TEST(Ros2Bag, NonCdrTopicIsRefusedByName) {
  const std::string path = kFixtures + "/with_json.mcap";
  try {
    OpenRos2Bag(path, {});
    FAIL() << "a json topic was accepted as CDR";
  } catch (const FormatError& error) {
    const std::string what = error.what();
    ExpectOneLineFrom(what, path);
    EXPECT_NE(what.find("/diagnostics_json"), std::string::npos) << what;
    EXPECT_NE(what.find("json"), std::string::npos) << what;
  }
  const auto reader = OpenRos2Bag(path, {"/odom"});
  const std::vector<BagMessage> messages = ReadAll(reader.get());
  EXPECT_EQ(messages.size(), 100u);
}

TEST(Ros2Bag, Db3NonCdrSerializationIsRefusedByName) {
  const ScratchFolder scratch;
  const std::string path = scratch.File("json.db3");
  fs::copy_file(kFixtures + "/db3_bag/db3_bag_0.db3", path);
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db,
                         "UPDATE topics SET serialization_format = 'json' "
                         "WHERE name = '/joint_states'",
                         nullptr,
                         nullptr,
                         nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  const std::string error = ReadError(path);
  EXPECT_NE(error.find("/joint_states"), std::string::npos) << error;
  EXPECT_NE(error.find("'json'"), std::string::npos) << error;
  const auto reader = OpenRos2Bag(path, {"/odom"});
  EXPECT_EQ(ReadAll(reader.get()).size(), 100u);
}

// A bag cut anywhere reads as a prefix of its messages (a recording that
// was stopped) or fails with a FormatError; it never crashes.
void ExpectTruncationsAreSafe(const std::string& name, size_t step) {
  const ScratchFolder scratch;
  const std::vector<uint8_t> bytes = ReadFile(kFixtures + "/" + name);
  const std::vector<ExpectedMessage> expected = ExpectedOrder(name);
  const std::string path = scratch.File("cut.mcap");
  size_t failures = 0;
  size_t complete = 0;
  for (size_t size = 0; size < bytes.size(); size += step) {
    SCOPED_TRACE("cut at " + std::to_string(size));
    WriteFile(path, std::vector<uint8_t>(bytes.begin(), bytes.begin() + size));
    std::vector<BagMessage> messages;
    std::string error;
    if (!TryReadAll(path, &messages, &error)) {
      ExpectOneLineFrom(error, path);
      ++failures;
      continue;
    }
    ASSERT_LE(messages.size(), expected.size());
    for (size_t i = 0; i < messages.size(); ++i) {
      ASSERT_EQ(messages[i].data, expected[i].bytes) << "message " << i;
      ASSERT_EQ(messages[i].log_time_ns, expected[i].log_time_ns);
    }
    if (messages.size() == expected.size()) ++complete;
  }
  EXPECT_GT(failures, 0u) << "the shortest cuts are not MCAP files";
  EXPECT_GT(complete, 0u) << "a cut in the summary keeps every message";
}

TEST(Ros2BagCorruption, TruncatedZstdMcap) {
  ExpectTruncationsAreSafe("zstd.mcap", 37);
}
TEST(Ros2BagCorruption, TruncatedLz4Mcap) {
  ExpectTruncationsAreSafe("lz4.mcap", 41);
}
TEST(Ros2BagCorruption, TruncatedUncompressedMcap) {
  ExpectTruncationsAreSafe("none.mcap", 113);
}
TEST(Ros2BagCorruption, TruncatedUnchunkedMcap) {
  ExpectTruncationsAreSafe("unchunked.mcap", 107);
}

TEST(Ros2BagCorruption, TruncatedDb3FailsOrReadsWrittenMessages) {
  const ScratchFolder scratch;
  const std::vector<uint8_t> bytes =
      ReadFile(kFixtures + "/db3_bag/db3_bag_0.db3");
  const std::string path = scratch.File("cut.db3");
  std::set<std::vector<uint8_t>> written;
  for (const ExpectedMessage& m : ExpectedMessages()) written.insert(m.bytes);
  size_t failures = 0;
  for (size_t size = 0; size < bytes.size(); size += 1531) {
    SCOPED_TRACE("cut at " + std::to_string(size));
    WriteFile(path, std::vector<uint8_t>(bytes.begin(), bytes.begin() + size));
    std::vector<BagMessage> messages;
    std::string error;
    if (!TryReadAll(path, &messages, &error)) {
      ExpectOneLineFrom(error, path);
      ++failures;
      continue;
    }
    for (const BagMessage& m : messages) EXPECT_EQ(written.count(m.data), 1u);
  }
  EXPECT_GT(failures, 0u);
}

TEST(Ros2BagCorruption, UnknownChunkCompressionNamesIt) {
  const ScratchFolder scratch;
  std::vector<uint8_t> bytes = ReadFile(kFixtures + "/zstd.mcap");
  const size_t chunk = McapRecordOffsets(bytes, 0x06).at(2);
  // The compression string follows 8 + 8 + 8 + 4 bytes of the chunk.
  const size_t name = chunk + 9 + 28 + 4;
  ASSERT_EQ(std::string(bytes.begin() + name, bytes.begin() + name + 4),
            "zstd");
  bytes[name + 3] = 'x';
  const std::string path = scratch.File("zstx.mcap");
  WriteFile(path, bytes);
  const std::string error = ReadError(path);
  EXPECT_EQ(error,
            path + ": chunk at byte " + std::to_string(chunk) +
                ": unknown compression 'zstx'");
}

TEST(Ros2BagCorruption, ChunkCrcMismatch) {
  const ScratchFolder scratch;
  for (const std::string name : {"zstd.mcap", "lz4.mcap", "none.mcap"}) {
    std::vector<uint8_t> bytes = ReadFile(kFixtures + "/" + name);
    const size_t chunk = McapRecordOffsets(bytes, 0x06).at(1);
    bytes[chunk + 9 + 24] ^= 0x01;  // uncompressed_crc
    const std::string path = scratch.File("crc_" + name);
    WriteFile(path, bytes);
    const std::string error = ReadError(path);
    EXPECT_NE(
        error.find("chunk at byte " + std::to_string(chunk) + ": CRC mismatch"),
        std::string::npos)
        << error;
  }
  // A flipped byte inside an uncompressed chunk's records.
  std::vector<uint8_t> bytes = ReadFile(kFixtures + "/none.mcap");
  const size_t chunk = McapRecordOffsets(bytes, 0x06).at(3);
  bytes[chunk + 200] ^= 0x40;
  const std::string path = scratch.File("payload.mcap");
  WriteFile(path, bytes);
  EXPECT_NE(ReadError(path).find("CRC mismatch"), std::string::npos);
}

TEST(Ros2BagCorruption, BadLengths) {
  const ScratchFolder scratch;
  const std::vector<uint8_t> original = ReadFile(kFixtures + "/zstd.mcap");
  const size_t chunk = McapRecordOffsets(original, 0x06).at(1);
  const std::string path = scratch.File("length.mcap");
  struct Case {
    size_t at;
    uint64_t value;
    const char* message;
  };
  const uint64_t huge = uint64_t{1} << 62;
  for (const Case& c : {
           Case{chunk + 1, huge, "runs past the end of the data section"},
           Case{chunk + 1, Le64(original, chunk + 1) - 5, "chunk at byte"},
           Case{chunk + 9 + 16, ~uint64_t{0}, "too large"},
           Case{chunk + 9 + 16, uint64_t{1} << 40, "inflates to"},
           Case{chunk + 9 + 16,
                Le64(original, chunk + 9 + 16) + 1,
                "inflates to"},
           Case{chunk + 9 + 32 + 4, huge, "records length"},
       }) {
    SCOPED_TRACE(c.message);
    std::vector<uint8_t> bytes = original;
    PutLe64(&bytes, c.at, c.value);
    WriteFile(path, bytes);
    const std::string error = ReadError(path);
    EXPECT_NE(error.find(c.message), std::string::npos) << error;
  }
  // The footer's summary start past the file's end.
  std::vector<uint8_t> bytes = original;
  PutLe64(&bytes, bytes.size() - 8 - 20, bytes.size() * 2);
  WriteFile(path, bytes);
  EXPECT_NE(ReadError(path).find("summary start"), std::string::npos);
}

TEST(Ros2BagCorruption, SummaryCrcMismatch) {
  const ScratchFolder scratch;
  std::vector<uint8_t> bytes = ReadFile(kFixtures + "/zstd.mcap");
  const size_t summary =
      static_cast<size_t>(Le64(bytes, bytes.size() - 8 - 20));
  bytes[summary + 20] ^= 0x10;
  const std::string path = scratch.File("summary.mcap");
  WriteFile(path, bytes);
  EXPECT_NE(ReadError(path).find("summary CRC mismatch"), std::string::npos);
}

TEST(Ros2BagCorruption, BadMagic) {
  const ScratchFolder scratch;
  std::vector<uint8_t> bytes = ReadFile(kFixtures + "/zstd.mcap");
  bytes[1] = 'X';
  const std::string path = scratch.File("magic.mcap");
  WriteFile(path, bytes);
  EXPECT_FALSE(LooksLikeRos2Bag(path));
  EXPECT_NE(ReadError(path).find("not a ROS 2 bag"), std::string::npos);
}

// Single flipped bytes all over a file: read or FormatError, nothing else.
TEST(Ros2BagCorruption, FlippedBytesNeverCrash) {
  const ScratchFolder scratch;
  for (const std::string name : {"zstd.mcap", "lz4.mcap", "unchunked.mcap"}) {
    const std::vector<uint8_t> original = ReadFile(kFixtures + "/" + name);
    const std::string path = scratch.File("flip_" + name);
    for (size_t at = 3; at < original.size(); at += 97) {
      SCOPED_TRACE(name + " byte " + std::to_string(at));
      std::vector<uint8_t> bytes = original;
      bytes[at] ^= static_cast<uint8_t>(0x5a + at);
      WriteFile(path, bytes);
      std::vector<BagMessage> messages;
      std::string error;
      if (!TryReadAll(path, &messages, &error)) ExpectOneLineFrom(error, path);
    }
  }
}

class Ros2FolderTest : public testing::Test {
 protected:
  // A copy of the fixture folder `name` with metadata.yaml replaced by
  // `edit` applied to it.
  std::string Copy(const std::string& name) {
    const std::string folder = scratch_.File(name);
    fs::copy(kFixtures + "/" + name, folder, fs::copy_options::recursive);
    return folder;
  }
  static void EditMetadata(const std::string& folder,
                           const std::string& from,
                           const std::string& to) {
    const std::string path = folder + "/metadata.yaml";
    const std::vector<uint8_t> bytes = ReadFile(path);
    std::string text(bytes.begin(), bytes.end());
    const size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    WriteFile(path, std::vector<uint8_t>(text.begin(), text.end()));
  }

  ScratchFolder scratch_;
};

TEST_F(Ros2FolderTest, MissingStorageFileIsNamed) {
  const std::string folder = Copy("split_bag");
  fs::remove(folder + "/split_bag_1.db3");
  const std::string error = ReadError(folder);
  EXPECT_NE(error.find("split_bag_1.db3"), std::string::npos) << error;
}

TEST_F(Ros2FolderTest, UnknownStorageIsRefused) {
  const std::string folder = Copy("db3_bag");
  EditMetadata(
      folder, "storage_identifier: sqlite3", "storage_identifier: rosbag_v2");
  EXPECT_NE(ReadError(folder).find("unknown storage_identifier 'rosbag_v2'"),
            std::string::npos);
}

TEST_F(Ros2FolderTest, FileCompressionIsRefused) {
  const std::string folder = Copy("db3_bag");
  EditMetadata(folder, "compression_format: \"\"", "compression_format: zstd");
  EditMetadata(folder, "compression_mode: \"\"", "compression_mode: FILE");
  const std::string error = ReadError(folder);
  EXPECT_NE(error.find("compression_mode 'FILE'"), std::string::npos) << error;
}

TEST_F(Ros2FolderTest, MessageCompressionOfUncompressedMessages) {
  const std::string folder = Copy("db3_bag");
  EditMetadata(folder, "compression_format: \"\"", "compression_format: zstd");
  EditMetadata(folder, "compression_mode: \"\"", "compression_mode: MESSAGE");
  const std::string error = ReadError(folder);
  EXPECT_NE(error.find("db3_bag_0.db3: message logged at "), std::string::npos)
      << error;
  EXPECT_NE(error.find("not a zstd frame"), std::string::npos) << error;
}

TEST_F(Ros2FolderTest, MalformedMetadataIsRefused) {
  const std::string folder = Copy("db3_bag");
  EditMetadata(
      folder, "relative_file_paths:", "relative_file_paths: [unclosed");
  EXPECT_NE(ReadError(folder).find("metadata.yaml"), std::string::npos);
}

TEST_F(Ros2FolderTest, FolderWithoutMetadata) {
  const std::string folder = Copy("db3_bag");
  fs::remove(folder + "/metadata.yaml");
  EXPECT_FALSE(LooksLikeRos2Bag(folder));
  EXPECT_NE(ReadError(folder).find("without metadata.yaml"), std::string::npos);
}

TEST_F(Ros2FolderTest, StorageOfTheWrongKind) {
  const std::string folder = Copy("mcap_bag");
  EditMetadata(
      folder, "storage_identifier: mcap", "storage_identifier: sqlite3");
  EXPECT_NE(ReadError(folder).find("mcap_bag_0.mcap"), std::string::npos);
}

// Bags recorded by rosbag2 itself, against their metadata.yaml.
class RecordedByRosbag2Test : public testing::TestWithParam<std::string> {};

TEST_P(RecordedByRosbag2Test, TopicsAndMessagesMatchTheMetadata) {
  const std::string path =
      std::string(ODOMCAL_ROSBAG2_RECORDED) + "/" + GetParam();
  const YAML::Node info =
      YAML::LoadFile(path + "/metadata.yaml")["rosbag2_bagfile_information"];
  std::map<std::string, std::pair<std::string, int64_t>> expected;
  for (const YAML::Node& topic : info["topics_with_message_count"]) {
    std::string type = topic["topic_metadata"]["type"].as<std::string>();
    type.replace(type.find("/msg/"), 5, "/");
    expected[topic["topic_metadata"]["name"].as<std::string>()] = {
        type, topic["message_count"].as<int64_t>()};
  }
  const int64_t start =
      info["starting_time"]["nanoseconds_since_epoch"].as<int64_t>();
  const int64_t end = start + info["duration"]["nanoseconds"].as<int64_t>();

  const auto reader = OpenRos2Bag(path, {});
  ASSERT_EQ(reader->Topics().size(), expected.size());
  int64_t first = 0;
  int64_t last = 0;
  for (const BagTopic& topic : reader->Topics()) {
    ASSERT_EQ(expected.count(topic.topic), 1u) << topic.topic;
    EXPECT_EQ(topic.type, expected[topic.topic].first);
    EXPECT_EQ(topic.message_count, expected[topic.topic].second);
    if (topic.message_count == 0) continue;
    first = first == 0 ? topic.first_log_time_ns
                       : std::min(first, topic.first_log_time_ns);
    last = std::max(last, topic.last_log_time_ns);
  }
  EXPECT_EQ(first, start);
  EXPECT_EQ(last, end);

  // /topic: std_msgs/String "Hello, world! N" in CDR (little-endian
  // encapsulation 00 01 00 00, uint32 length with the '\0', the bytes).
  const auto talker = OpenRos2Bag(path, {"/topic"});
  const std::vector<BagMessage> messages = ReadAll(talker.get());
  ASSERT_EQ(messages.size(), 10u);
  for (size_t i = 0; i < messages.size(); ++i) {
    const std::vector<uint8_t>& data = messages[i].data;
    const std::string text = "Hello, world! " + std::to_string(i);
    std::vector<uint8_t> want = {
        0, 1, 0, 0, static_cast<uint8_t>(text.size() + 1), 0, 0, 0};
    want.insert(want.end(), text.begin(), text.end());
    want.push_back(0);
    EXPECT_EQ(data, want) << "message " << i;
    if (i > 0) {
      EXPECT_GT(messages[i].log_time_ns, messages[i - 1].log_time_ns);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Talker,
                         RecordedByRosbag2Test,
                         testing::Values("talker_sqlite3", "talker_mcap"),
                         ParamName);

TEST(Ros2Bag, NotABag) {
  const ScratchFolder scratch;
  const std::string path = scratch.File("notes.txt");
  const std::string text = "not a bag\n";
  WriteFile(path, std::vector<uint8_t>(text.begin(), text.end()));
  EXPECT_FALSE(LooksLikeRos2Bag(path));
  EXPECT_NE(ReadError(path).find("not a ROS 2 bag"), std::string::npos);
  EXPECT_NE(ReadError(scratch.File("missing.mcap")).find("no such file"),
            std::string::npos);
}

}  // namespace
}  // namespace odomcal::bag
