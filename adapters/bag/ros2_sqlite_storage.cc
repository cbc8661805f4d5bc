// rosbag2's SQLite storage. Every version of rosbag2_storage_sqlite3 has the
// columns read here (topics: id, name, type, serialization_format; messages:
// id, topic_id, timestamp, data); the later columns and tables (QoS, type
// hashes, schema, metadata, message_definitions) are not needed.
#include "odomcal/adapters/bag/ros2_sqlite_storage.h"

#include "odomcal/adapters/format_error.h"

#include <sqlite3.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace odomcal::bag::internal {
namespace {

namespace fs = std::filesystem;

struct SqliteCloser {
  void operator()(sqlite3* database) const { sqlite3_close(database); }
};
struct SqliteFinalizer {
  void operator()(sqlite3_stmt* statement) const {
    sqlite3_finalize(statement);
  }
};
using SqliteHandle = std::unique_ptr<sqlite3, SqliteCloser>;
using SqliteStatement = std::unique_ptr<sqlite3_stmt, SqliteFinalizer>;

[[noreturn]] void SqliteFail(const std::string& path, const std::string& what) {
  throw FormatError(path + ": " + what);
}

// A "file:" URI with everything but unreserved characters and '/'
// percent-encoded, so that '?', '#' and '%' in a path stay part of it.
std::string SqliteUri(const std::string& path) {
  static const char kHex[] = "0123456789ABCDEF";
  std::string uri = path.front() == '/' ? "file://" : "file:";
  for (const char c : path) {
    const unsigned char byte = static_cast<unsigned char>(c);
    if ((byte >= 'a' && byte <= 'z') || (byte >= 'A' && byte <= 'Z') ||
        (byte >= '0' && byte <= '9') || std::strchr("-._~/", c) != nullptr) {
      uri.push_back(c);
    } else {
      uri.push_back('%');
      uri.push_back(kHex[byte >> 4]);
      uri.push_back(kHex[byte & 0xf]);
    }
  }
  return uri + "?mode=ro&immutable=1";
}

SqliteHandle SqliteOpenReadOnly(const std::string& path) {
  std::error_code error;
  if (path.empty() || !fs::is_regular_file(path, error)) {
    SqliteFail(path,
               fs::exists(path, error)
                   ? "cannot open the rosbag2 database: not a regular file"
                   : "cannot open the rosbag2 database: no such file");
  }
  sqlite3* raw = nullptr;
  const int status = sqlite3_open_v2(SqliteUri(path).c_str(),
                                     &raw,
                                     SQLITE_OPEN_READONLY | SQLITE_OPEN_URI,
                                     nullptr);
  SqliteHandle database(raw);
  if (status != SQLITE_OK) {
    SqliteFail(
        path,
        std::string("cannot open the rosbag2 database: ") +
            (raw != nullptr ? sqlite3_errmsg(raw) : sqlite3_errstr(status)));
  }
  return database;
}

SqliteStatement SqlitePrepare(sqlite3* database,
                              const std::string& path,
                              const std::string& sql) {
  sqlite3_stmt* raw = nullptr;
  const int status =
      sqlite3_prepare_v2(database, sql.c_str(), -1, &raw, nullptr);
  SqliteStatement statement(raw);
  if (status != SQLITE_OK) {
    SqliteFail(path,
               std::string("not a rosbag2 SQLite database: ") +
                   sqlite3_errmsg(database));
  }
  return statement;
}

bool SqliteStep(sqlite3* database,
                sqlite3_stmt* statement,
                const std::string& path) {
  const int status = sqlite3_step(statement);
  if (status == SQLITE_ROW) return true;
  if (status == SQLITE_DONE) return false;
  SqliteFail(path,
             std::string("cannot read the rosbag2 database: ") +
                 sqlite3_errmsg(database));
}

std::string SqliteText(sqlite3_stmt* statement,
                       int column,
                       const std::string& path,
                       const char* what) {
  if (sqlite3_column_type(statement, column) != SQLITE_TEXT) {
    SqliteFail(path, std::string("topics: ") + what + " is not text");
  }
  const unsigned char* text = sqlite3_column_text(statement, column);
  const int size = sqlite3_column_bytes(statement, column);
  return std::string(reinterpret_cast<const char*>(text),
                     static_cast<size_t>(size));
}

int64_t SqliteInteger(sqlite3_stmt* statement,
                      int column,
                      const std::string& path,
                      const char* what) {
  if (sqlite3_column_type(statement, column) != SQLITE_INTEGER) {
    SqliteFail(path, std::string(what) + " is not an integer");
  }
  return sqlite3_column_int64(statement, column);
}

class SqliteRos2Storage final : public Ros2Storage {
 public:
  explicit SqliteRos2Storage(std::string path)
      : path_(std::move(path)), database_(SqliteOpenReadOnly(path_)) {
    ReadTopics();
    ReadCounts();
    selected_.assign(topics_.size(), true);
  }

  const std::vector<Ros2StorageTopic>& Topics() const override {
    return topics_;
  }

  void Select(const std::vector<bool>& selected) override {
    selected_ = selected;
    selected_.resize(topics_.size(), false);
  }

  bool Next(BagMessage* message) override {
    if (!messages_) Prepare();
    while (SqliteStep(database_.get(), messages_.get(), path_)) {
      const int64_t topic_id =
          SqliteInteger(messages_.get(), 0, path_, "messages: topic_id");
      const auto topic = index_of_id_.find(topic_id);
      if (topic == index_of_id_.end()) {
        SqliteFail(path_,
                   "messages: topic_id " + std::to_string(topic_id) +
                       " is not in the topics table");
      }
      if (!selected_[topic->second]) continue;
      message->topic_index = topic->second;
      message->log_time_ns =
          SqliteInteger(messages_.get(), 1, path_, "messages: timestamp");
      const int type = sqlite3_column_type(messages_.get(), 2);
      if (type != SQLITE_BLOB && type != SQLITE_NULL) {
        SqliteFail(path_, "messages: data is not a blob");
      }
      const void* blob = sqlite3_column_blob(messages_.get(), 2);
      const int size = sqlite3_column_bytes(messages_.get(), 2);
      const auto* bytes = static_cast<const uint8_t*>(blob);
      if (size > 0) {
        message->data.assign(bytes, bytes + size);
      } else {
        message->data.clear();
      }
      return true;
    }
    return false;
  }

 private:
  void ReadTopics() {
    const SqliteStatement statement = SqlitePrepare(
        database_.get(),
        path_,
        "SELECT id, name, type, serialization_format FROM topics ORDER BY id");
    while (SqliteStep(database_.get(), statement.get(), path_)) {
      const int64_t id = SqliteInteger(statement.get(), 0, path_, "topics: id");
      Ros2StorageTopic topic;
      topic.topic.topic = SqliteText(statement.get(), 1, path_, "name");
      topic.topic.type =
          NormaliseRos2Type(SqliteText(statement.get(), 2, path_, "type"));
      topic.topic.encoding = MessageEncoding::kCdr;
      const std::string format =
          SqliteText(statement.get(), 3, path_, "serialization_format");
      if (format != "cdr") {
        topic.refusal =
            "serialization format " + Ros2Quoted(format) + ", not 'cdr'";
      }
      if (!index_of_id_.emplace(id, topics_.size()).second) {
        SqliteFail(path_, "topics: id " + std::to_string(id) + " twice");
      }
      topics_.push_back(std::move(topic));
    }
  }

  // Counts and time spans: one pass over the messages' fixed columns (SQLite
  // reads a blob's overflow pages only when the blob itself is asked for).
  void ReadCounts() {
    const SqliteStatement statement = SqlitePrepare(
        database_.get(),
        path_,
        "SELECT topic_id, COUNT(*), MIN(timestamp), MAX(timestamp) "
        "FROM messages GROUP BY topic_id");
    while (SqliteStep(database_.get(), statement.get(), path_)) {
      const int64_t topic_id =
          SqliteInteger(statement.get(), 0, path_, "messages: topic_id");
      const auto topic = index_of_id_.find(topic_id);
      if (topic == index_of_id_.end()) {
        SqliteFail(path_,
                   "messages: topic_id " + std::to_string(topic_id) +
                       " is not in the topics table");
      }
      BagTopic& info = topics_[topic->second].topic;
      info.message_count = sqlite3_column_int64(statement.get(), 1);
      info.first_log_time_ns =
          SqliteInteger(statement.get(), 2, path_, "messages: timestamp");
      info.last_log_time_ns =
          SqliteInteger(statement.get(), 3, path_, "messages: timestamp");
    }
  }

  // Timestamp order through rosbag2's index on timestamp; a database without
  // that index (none of rosbag2's) would sort whole rows, so it streams in
  // row order instead.
  void Prepare() {
    const SqliteStatement has_index = SqlitePrepare(
        database_.get(),
        path_,
        "SELECT COUNT(*) FROM sqlite_master WHERE type = 'index' AND "
        "tbl_name = 'messages' AND sql LIKE '%(timestamp%'");
    const bool by_time = SqliteStep(database_.get(), has_index.get(), path_) &&
                         sqlite3_column_int64(has_index.get(), 0) > 0;
    messages_ = SqlitePrepare(
        database_.get(),
        path_,
        by_time ? "SELECT topic_id, timestamp, data FROM messages "
                  "ORDER BY timestamp, id"
                : "SELECT topic_id, timestamp, data FROM messages ORDER BY id");
  }

  std::string path_;
  SqliteHandle database_;
  std::vector<Ros2StorageTopic> topics_;
  std::map<int64_t, size_t> index_of_id_;
  std::vector<bool> selected_;
  SqliteStatement messages_;
};

}  // namespace

std::unique_ptr<Ros2Storage> OpenRos2SqliteStorage(const std::string& path) {
  return std::make_unique<SqliteRos2Storage>(path);
}

bool LooksLikeSqliteFile(const std::string& path) {
  static const char kSqliteMagic[16] = "SQLite format 3";  // with its '\0'
  std::ifstream file(path, std::ios::binary);
  char head[16] = {};
  if (!file.read(head, sizeof(head))) return false;
  return std::memcmp(head, kSqliteMagic, sizeof(head)) == 0;
}

}  // namespace odomcal::bag::internal
