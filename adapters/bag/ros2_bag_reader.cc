// ROS 2 bags (ros2_bag_reader.h): a rosbag2 folder (metadata.yaml and the
// storage files it lists, read one after the other) or a single storage
// file, recognised by its content.
#include "odomcal/adapters/bag/ros2_bag_reader.h"

#include "odomcal/adapters/bag/mcap_records.h"
#include "odomcal/adapters/bag/mcap_storage.h"
#include "odomcal/adapters/bag/ros2_sqlite_storage.h"
#include "odomcal/adapters/bag/ros2_storage.h"
#include "odomcal/adapters/format_error.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace odomcal::bag {
namespace internal {

std::string NormaliseRos2Type(const std::string& type) {
  const size_t first = type.find('/');
  if (first == std::string::npos) return type;
  const size_t second = type.find('/', first + 1);
  if (second == std::string::npos ||
      type.find('/', second + 1) != std::string::npos ||
      type.compare(first + 1, second - first - 1, "msg") != 0) {
    return type;
  }
  return type.substr(0, first) + type.substr(second);
}

std::string Ros2Quoted(const std::string& text) {
  static const char kHex[] = "0123456789abcdef";
  constexpr size_t kMaxShown = 100;
  std::string quoted = "'";
  for (size_t i = 0; i < text.size() && i < kMaxShown; ++i) {
    const unsigned char byte = static_cast<unsigned char>(text[i]);
    if (byte >= 0x20 && byte < 0x7f && byte != '\\') {
      quoted.push_back(static_cast<char>(byte));
    } else {
      quoted += "\\x";
      quoted.push_back(kHex[byte >> 4]);
      quoted.push_back(kHex[byte & 0xf]);
    }
  }
  if (text.size() > kMaxShown) quoted += "...";
  return quoted + "'";
}

}  // namespace internal

namespace {

namespace fs = std::filesystem;
using internal::Ros2Quoted;
using internal::Ros2Storage;
using internal::Ros2StorageTopic;

enum class Ros2StorageKind { kSqlite, kMcap };

struct Ros2File {
  std::string path;
  Ros2StorageKind kind = Ros2StorageKind::kSqlite;
};

struct Ros2Files {
  std::vector<Ros2File> files;
  // compression_mode MESSAGE, zstd: each message's data is one zstd frame.
  bool zstd_messages = false;
};

std::unique_ptr<Ros2Storage> OpenRos2Storage(const Ros2File& file) {
  return file.kind == Ros2StorageKind::kMcap
             ? internal::OpenMcapStorage(file.path)
             : internal::OpenRos2SqliteStorage(file.path);
}

std::string Ros2Upper(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) {
    return static_cast<char>(std::toupper(c));
  });
  return text;
}

// The keys of metadata.yaml (rosbag2_storage's BagMetadata) that say which
// files hold the messages and how.
Ros2Files ReadRos2Metadata(const std::string& folder) {
  const std::string path = (fs::path(folder) / "metadata.yaml").string();
  const auto fail = [&](const std::string& what) -> void {
    throw FormatError(path + ": " + what);
  };
  YAML::Node bag;
  int version = 0;
  std::string storage;
  std::string compression_mode;
  std::string compression_format;
  std::vector<std::string> relative_paths;
  try {
    bag = YAML::LoadFile(path)["rosbag2_bagfile_information"];
    if (!bag.IsMap()) fail("no rosbag2_bagfile_information map");
    version = bag["version"].as<int>();
    storage = bag["storage_identifier"].as<std::string>();
    relative_paths = bag["relative_file_paths"].as<std::vector<std::string>>();
    if (bag["compression_mode"]) {
      compression_mode = bag["compression_mode"].as<std::string>();
    }
    if (bag["compression_format"]) {
      compression_format = bag["compression_format"].as<std::string>();
    }
  } catch (const YAML::Exception& error) {
    std::string what = error.what();
    std::replace(what.begin(), what.end(), '\n', ' ');
    fail("not a rosbag2 metadata file: " + what);
  }
  Ros2StorageKind kind = Ros2StorageKind::kSqlite;
  if (storage == "mcap") {
    kind = Ros2StorageKind::kMcap;
  } else if (storage != "sqlite3") {
    fail("unknown storage_identifier " + Ros2Quoted(storage) +
         " (readable: sqlite3, mcap)");
  }
  // FILE compresses whole storage files (.db3.zstd), which SQLite cannot
  // open in place; MESSAGE compresses each message on its own.
  Ros2Files result;
  const std::string mode = Ros2Upper(compression_mode);
  if (mode == "MESSAGE" && compression_format == "zstd") {
    result.zstd_messages = true;
  } else if (!mode.empty() && mode != "NONE") {
    fail("compression_mode " + Ros2Quoted(compression_mode) + " (" +
         Ros2Quoted(compression_format) +
         ") is not supported: decompress the bag first (ros2 bag convert)");
  }
  if (relative_paths.empty()) fail("relative_file_paths lists no file");
  // Up to version 3, rosbag2 wrote the paths with the bag folder's name.
  const fs::path base =
      version < 4 ? fs::path(folder).parent_path() : fs::path(folder);
  for (const std::string& relative : relative_paths) {
    const fs::path file =
        fs::path(relative).is_absolute() ? fs::path(relative) : base / relative;
    std::error_code error;
    if (!fs::is_regular_file(file, error)) {
      fail("lists " + Ros2Quoted(relative) + ", which is not a file in " +
           folder);
    }
    result.files.push_back({file.string(), kind});
  }
  return result;
}

class Ros2BagReader final : public BagReader {
 public:
  Ros2BagReader(std::string path,
                Ros2Files files,
                const std::vector<std::string>& topics)
      : path_(std::move(path)),
        files_(std::move(files.files)),
        zstd_messages_(files.zstd_messages) {
    for (size_t i = 0; i < files_.size(); ++i) {
      std::unique_ptr<Ros2Storage> storage = OpenRos2Storage(files_[i]);
      std::vector<size_t> merged;
      for (const Ros2StorageTopic& topic : storage->Topics()) {
        merged.push_back(Merge(topic, files_[i].path));
      }
      file_topics_.push_back(std::move(merged));
      if (i == 0) storage_ = std::move(storage);
    }
    Select(topics);
  }

  const std::string& Path() const override { return path_; }
  const std::vector<BagTopic>& Topics() const override { return topics_; }

  bool Next(BagMessage* message) override {
    while (file_ < files_.size()) {
      if (!storage_) storage_ = OpenRos2Storage(files_[file_]);
      if (!selected_in_file_) {
        std::vector<bool> selected;
        for (const size_t topic : file_topics_[file_]) {
          selected.push_back(selected_[topic]);
        }
        storage_->Select(selected);
        selected_in_file_ = true;
      }
      if (storage_->Next(message)) {
        message->topic_index = file_topics_[file_][message->topic_index];
        if (zstd_messages_) {
          internal::InflateZstdFrame(
              message->data.data(),
              message->data.size(),
              files_[file_].path + ": message logged at " +
                  std::to_string(message->log_time_ns) + " ns",
              &inflated_);
          message->data.swap(inflated_);
        }
        return true;
      }
      storage_.reset();
      selected_in_file_ = false;
      ++file_;
    }
    return false;
  }

 private:
  // The index in topics_ of a file's topic, adding it or adding to it.
  size_t Merge(const Ros2StorageTopic& topic, const std::string& file) {
    for (size_t i = 0; i < topics_.size(); ++i) {
      BagTopic& known = topics_[i];
      if (known.topic != topic.topic.topic) continue;
      if (known.type != topic.topic.type) {
        throw FormatError(file + ": topic " + Ros2Quoted(known.topic) +
                          " has type " + Ros2Quoted(topic.topic.type) +
                          ", an earlier file " + Ros2Quoted(known.type));
      }
      if (refusals_[i].empty()) refusals_[i] = topic.refusal;
      AddMessagesOf(topic.topic, &known);
      return i;
    }
    topics_.push_back(topic.topic);
    refusals_.push_back(topic.refusal);
    return topics_.size() - 1;
  }

  void Select(const std::vector<std::string>& names) {
    selected_.assign(topics_.size(), names.empty());
    for (const std::string& name : names) {
      const auto it =
          std::find_if(topics_.begin(), topics_.end(), [&](const BagTopic& t) {
            return t.topic == name;
          });
      if (it == topics_.end()) {
        std::string known;
        for (const BagTopic& topic : topics_) {
          known += (known.empty() ? "" : ", ") + Ros2Quoted(topic.topic);
        }
        throw FormatError(path_ + ": no topic " + Ros2Quoted(name) +
                          " in the bag (its topics: " +
                          (known.empty() ? "none" : known) + ")");
      }
      selected_[static_cast<size_t>(it - topics_.begin())] = true;
    }
    for (size_t i = 0; i < topics_.size(); ++i) {
      if (selected_[i] && !refusals_[i].empty()) {
        throw FormatError(
            path_ + ": topic " + Ros2Quoted(topics_[i].topic) +
            " is not readable as ROS 2 CDR: " + refusals_[i] +
            (names.empty() ? " (select the topics to read)" : ""));
      }
    }
  }

  std::string path_;
  std::vector<Ros2File> files_;
  bool zstd_messages_ = false;
  std::vector<uint8_t> inflated_;
  std::vector<BagTopic> topics_;
  std::vector<std::string> refusals_;
  // Per file: its topics' indexes in topics_.
  std::vector<std::vector<size_t>> file_topics_;
  std::vector<bool> selected_;

  size_t file_ = 0;
  std::unique_ptr<Ros2Storage> storage_;
  bool selected_in_file_ = false;
};

}  // namespace

bool LooksLikeRos2Bag(const std::string& path) {
  std::error_code error;
  if (fs::is_directory(path, error)) {
    return fs::is_regular_file(fs::path(path) / "metadata.yaml", error);
  }
  return internal::LooksLikeMcapFile(path) ||
         internal::LooksLikeSqliteFile(path);
}

std::unique_ptr<BagReader> OpenRos2Bag(const std::string& path,
                                       const std::vector<std::string>& topics) {
  std::error_code error;
  Ros2Files files;
  if (fs::is_directory(path, error)) {
    if (!fs::is_regular_file(fs::path(path) / "metadata.yaml", error)) {
      throw FormatError(path +
                        ": a folder without metadata.yaml, not a rosbag2 bag");
    }
    files = ReadRos2Metadata(path);
  } else if (!fs::exists(path, error)) {
    throw FormatError(path + ": no such file or folder");
  } else if (internal::LooksLikeMcapFile(path)) {
    files.files.push_back({path, Ros2StorageKind::kMcap});
  } else if (internal::LooksLikeSqliteFile(path)) {
    files.files.push_back({path, Ros2StorageKind::kSqlite});
  } else {
    throw FormatError(
        path +
        ": not a ROS 2 bag (neither an MCAP file, an SQLite database "
        "nor a folder with metadata.yaml)");
  }
  return std::make_unique<Ros2BagReader>(path, std::move(files), topics);
}

}  // namespace odomcal::bag
