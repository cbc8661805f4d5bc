// Opens the database through a percent-encoded "file:" URI with
// mode=ro&immutable=1 and SQLITE_OPEN_READONLY | SQLITE_OPEN_URI, runs one
// SELECT per table, and converts each row with range checks. Handles are
// owned by small RAII wrappers so that every throw closes them. Nothing is
// ever written: no PRAGMA, no transaction, no schema change.
#include "odomcal/adapters/colmap_database.h"

#include "odomcal/adapters/format_error.h"

#include <sqlite3.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

// Percent-encodes everything but unreserved characters and '/', so that '?',
// '#' and '%' in a path are not taken for URI syntax.
std::string DatabaseUri(const std::string& path) {
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

struct DatabaseCloser {
  void operator()(sqlite3* database) const { sqlite3_close(database); }
};
struct StatementFinalizer {
  void operator()(sqlite3_stmt* statement) const {
    sqlite3_finalize(statement);
  }
};
using DatabaseHandle = std::unique_ptr<sqlite3, DatabaseCloser>;
using StatementHandle = std::unique_ptr<sqlite3_stmt, StatementFinalizer>;

[[noreturn]] void Fail(const std::string& path, const std::string& what) {
  throw FormatError(path + ": " + what);
}

DatabaseHandle OpenReadOnly(const std::string& path) {
  std::error_code error;
  if (path.empty() || !fs::is_regular_file(path, error)) {
    Fail(path,
         fs::exists(path, error)
             ? "cannot open the COLMAP database: not a regular file"
             : "cannot open the COLMAP database: no such file");
  }
  sqlite3* raw = nullptr;
  const int status = sqlite3_open_v2(DatabaseUri(path).c_str(),
                                     &raw,
                                     SQLITE_OPEN_READONLY | SQLITE_OPEN_URI,
                                     nullptr);
  DatabaseHandle database(raw);
  if (status != SQLITE_OK) {
    Fail(path,
         std::string("cannot open the COLMAP database: ") +
             (raw != nullptr ? sqlite3_errmsg(raw) : sqlite3_errstr(status)));
  }
  return database;
}

StatementHandle Prepare(sqlite3* database,
                        const std::string& path,
                        const char* sql,
                        const char* table) {
  sqlite3_stmt* raw = nullptr;
  const int status = sqlite3_prepare_v2(database, sql, -1, &raw, nullptr);
  StatementHandle statement(raw);
  if (status != SQLITE_OK) {
    Fail(path,
         std::string("not a readable COLMAP database (reading table '") +
             table + "'): " + sqlite3_errmsg(database));
  }
  return statement;
}

// Steps to the next row; false when done. Throws on SQLite errors.
bool NextRow(sqlite3* database,
             sqlite3_stmt* statement,
             const std::string& path) {
  const int status = sqlite3_step(statement);
  if (status == SQLITE_ROW) return true;
  if (status == SQLITE_DONE) return false;
  Fail(path,
       std::string("cannot read the COLMAP database: ") +
           sqlite3_errmsg(database));
}

int64_t IntegerColumn(sqlite3_stmt* statement,
                      int column,
                      const char* name,
                      int64_t min_value,
                      int64_t max_value,
                      const std::string& path,
                      const std::string& row) {
  if (sqlite3_column_type(statement, column) != SQLITE_INTEGER) {
    Fail(path, row + ": column " + name + " is not an integer");
  }
  const int64_t value = sqlite3_column_int64(statement, column);
  if (value < min_value || value > max_value) {
    Fail(path,
         row + ": " + name + " " + std::to_string(value) +
             " is out of range [" + std::to_string(min_value) + ", " +
             std::to_string(max_value) + "]");
  }
  return value;
}

constexpr int64_t kMaxId = std::numeric_limits<uint32_t>::max();
constexpr int64_t kMaxInt64 = std::numeric_limits<int64_t>::max();

}  // namespace

std::vector<ColmapDatabaseImage> ReadColmapDatabaseImages(
    const std::string& database_path) {
  const DatabaseHandle database = OpenReadOnly(database_path);
  const StatementHandle statement =
      Prepare(database.get(),
              database_path,
              "SELECT image_id, name, camera_id FROM images ORDER BY image_id",
              "images");
  std::vector<ColmapDatabaseImage> images;
  while (NextRow(database.get(), statement.get(), database_path)) {
    ColmapDatabaseImage image;
    const std::string row = "images row " + std::to_string(images.size() + 1);
    image.image_id = static_cast<uint32_t>(IntegerColumn(
        statement.get(), 0, "image_id", 0, kMaxId, database_path, row));
    const std::string row_with_id =
        "images row with image_id " + std::to_string(image.image_id);
    const unsigned char* name = sqlite3_column_text(statement.get(), 1);
    if (name == nullptr) Fail(database_path, row_with_id + ": name is NULL");
    image.name.assign(reinterpret_cast<const char*>(name),
                      sqlite3_column_bytes(statement.get(), 1));
    image.camera_id = static_cast<uint32_t>(IntegerColumn(statement.get(),
                                                          2,
                                                          "camera_id",
                                                          0,
                                                          kMaxId,
                                                          database_path,
                                                          row_with_id));
    images.push_back(std::move(image));
  }
  return images;
}

std::vector<ColmapDatabaseCamera> ReadColmapDatabaseCameras(
    const std::string& database_path) {
  const DatabaseHandle database = OpenReadOnly(database_path);
  const StatementHandle statement =
      Prepare(database.get(),
              database_path,
              "SELECT camera_id, model, width, height, params, "
              "prior_focal_length FROM cameras ORDER BY camera_id",
              "cameras");
  std::vector<ColmapDatabaseCamera> cameras;
  while (NextRow(database.get(), statement.get(), database_path)) {
    sqlite3_stmt* const row_values = statement.get();
    ColmapDatabaseCamera entry;
    ColmapCamera& camera = entry.camera;
    const std::string row = "cameras row " + std::to_string(cameras.size() + 1);
    camera.camera_id = static_cast<uint32_t>(IntegerColumn(
        row_values, 0, "camera_id", 0, kMaxId, database_path, row));
    const std::string row_with_id =
        "camera_id " + std::to_string(camera.camera_id);
    const int64_t model_id = IntegerColumn(row_values,
                                           1,
                                           "model",
                                           std::numeric_limits<int64_t>::min(),
                                           kMaxInt64,
                                           database_path,
                                           row_with_id);
    const std::optional<ColmapCameraModel> model =
        model_id >= 0 && model_id <= std::numeric_limits<int>::max()
            ? ColmapCameraModelFromId(static_cast<int>(model_id))
            : std::nullopt;
    if (!model) {
      Fail(database_path,
           row_with_id + ": unknown camera model id " +
               std::to_string(model_id) + " (COLMAP 3.8 models are 0 to 10)");
    }
    camera.model = *model;
    camera.width = static_cast<uint64_t>(IntegerColumn(
        row_values, 2, "width", 0, kMaxInt64, database_path, row_with_id));
    camera.height = static_cast<uint64_t>(IntegerColumn(
        row_values, 3, "height", 0, kMaxInt64, database_path, row_with_id));

    const int num_params = ColmapCameraModelNumParams(camera.model);
    const int blob_type = sqlite3_column_type(row_values, 4);
    if (blob_type != SQLITE_BLOB && blob_type != SQLITE_NULL) {
      Fail(database_path, row_with_id + ": params is not a blob");
    }
    const void* blob = sqlite3_column_blob(row_values, 4);
    const int num_bytes = sqlite3_column_bytes(row_values, 4);
    if (num_bytes != 8 * num_params) {
      Fail(database_path,
           row_with_id + ": params blob has " + std::to_string(num_bytes) +
               " bytes, model " + ColmapCameraModelName(camera.model) +
               " needs " + std::to_string(num_params) +
               " float64 = " + std::to_string(8 * num_params) + " bytes");
    }
    const unsigned char* bytes = static_cast<const unsigned char*>(blob);
    camera.params.resize(num_params);
    for (int k = 0; k < num_params; ++k) {
      uint64_t bits = 0;
      for (int b = 7; b >= 0; --b) bits = (bits << 8) | bytes[8 * k + b];
      std::memcpy(&camera.params[k], &bits, sizeof(double));
      if (!std::isfinite(camera.params[k])) {
        Fail(database_path,
             row_with_id + ": param " + std::to_string(k) + " is not finite");
      }
    }
    entry.prior_focal_length =
        IntegerColumn(row_values,
                      5,
                      "prior_focal_length",
                      std::numeric_limits<int64_t>::min(),
                      kMaxInt64,
                      database_path,
                      row_with_id) != 0;
    cameras.push_back(std::move(entry));
  }
  return cameras;
}

}  // namespace odomcal
