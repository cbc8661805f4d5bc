// Opens the database read-only (colmap_database_sqlite.cc), runs one
// SELECT per table (valid in every schema from COLMAP 3.8 to 4.1), and converts
// each row with range checks. Handles are owned by small RAII wrappers so that
// every throw closes them. Nothing is ever written: no PRAGMA, no transaction,
// no schema change.
#include "odomcal/adapters/colmap_database.h"

#include "odomcal/adapters/colmap_database_internal.h"
#include "odomcal/adapters/colmap_model_internal.h"
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

using internal::DatabaseHandle;
using internal::NextRow;
using internal::OpenReadOnly;
using internal::Prepare;
using internal::StatementHandle;

[[noreturn]] void Fail(const std::string& path, const std::string& what) {
  internal::FailDatabase(path, what);
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
           row_with_id + ": " + internal::UnknownModelIdText(model_id));
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
