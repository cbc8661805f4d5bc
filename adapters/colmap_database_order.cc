// One transaction of UPDATEs through a temporary table of old and new ids:
// every id is first moved out of the way (by kOffset), then set to its new
// value, so that no two rows ever share an id (image_id is a primary key).
#include "odomcal/adapters/colmap_database_order.h"

#include "odomcal/adapters/colmap_database_internal.h"
#include "odomcal/adapters/colmap_database_version.h"
#include "odomcal/adapters/format_error.h"

#include <sqlite3.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

namespace odomcal {
namespace {

using internal::DatabaseHandle;
using internal::StatementHandle;

// Above any id COLMAP assigns here (one per image), below COLMAP's
// image_id CHECK (< 2^31 - 1).
constexpr int64_t kOffset = int64_t{1} << 30;

// A column holding image (or frame) ids: table, column, and a condition on
// the row (empty: every row).
struct IdColumn {
  std::string table;
  std::string column;
  std::string where;
};

bool HasTable(sqlite3* db, const std::string& table) {
  sqlite3_stmt* raw = nullptr;
  sqlite3_prepare_v2(db,
                     "SELECT 1 FROM sqlite_master WHERE type = 'table' AND "
                     "name = ?1",
                     -1,
                     &raw,
                     nullptr);
  const StatementHandle statement(raw);
  sqlite3_bind_text(raw, 1, table.c_str(), -1, SQLITE_TRANSIENT);
  return sqlite3_step(raw) == SQLITE_ROW;
}

int64_t Count(sqlite3* db, const std::string& sql) {
  sqlite3_stmt* raw = nullptr;
  if (sqlite3_prepare_v2(db, sql.c_str(), -1, &raw, nullptr) != SQLITE_OK) {
    return -1;
  }
  const StatementHandle statement(raw);
  return sqlite3_step(raw) == SQLITE_ROW ? sqlite3_column_int64(raw, 0) : -1;
}

}  // namespace

bool RenumberColmapImagesByName(const std::string& database_path) {
  const DatabaseHandle db = internal::OpenReadWrite(database_path);
  const ColmapDatabaseVersion version =
      internal::InspectColmapDatabase(db.get(), database_path);
  if (!version.has_cameras_and_images) {
    throw FormatError(database_path + ": no COLMAP images table (" +
                      DescribeColmapDatabaseVersion(version) + ")");
  }
  // In name order already: nothing to do (and a rerun changes nothing).
  if (Count(db.get(),
            "SELECT COUNT(*) FROM (SELECT image_id, ROW_NUMBER() OVER (ORDER "
            "BY name) AS rank FROM images) WHERE image_id != rank") == 0) {
    return false;
  }
  for (const char* table : {"matches", "two_view_geometries"}) {
    if (HasTable(db.get(), table) &&
        Count(db.get(), std::string("SELECT COUNT(*) FROM ") + table) != 0) {
      throw FormatError(database_path + ": cannot renumber its images: its " +
                        table + " table is not empty");
    }
  }
  std::vector<IdColumn> images = {{"images", "image_id", ""},
                                  {"keypoints", "image_id", ""},
                                  {"descriptors", "image_id", ""}};
  switch (version.prior_layout) {
    case ColmapPriorLayout::kPosePriorsByImage:
    case ColmapPriorLayout::kPosePriorsWithCovariance:
      images.push_back({"pose_priors", "image_id", ""});
      break;
    case ColmapPriorLayout::kPosePriorsBySensor:
      images.push_back({"pose_priors", "corr_data_id", "corr_sensor_type = 0"});
      break;
    default:
      break;
  }
  // Sensor type 0 is a camera (COLMAP's SensorType::CAMERA).
  if (version.has_rigs_and_frames) {
    images.push_back({"frame_data", "data_id", "sensor_type = 0"});
  }
  std::vector<std::string> sql = {
      "BEGIN",
      "DROP TABLE IF EXISTS temp.odomcal_image_ids",
      "CREATE TEMP TABLE odomcal_image_ids AS SELECT image_id AS old_id, "
      "ROW_NUMBER() OVER (ORDER BY name) AS new_id FROM images"};
  const std::string offset = std::to_string(kOffset);
  auto renumber = [&](const std::vector<IdColumn>& columns,
                      const std::string& mapping) {
    for (const IdColumn& c : columns) {
      const std::string where = c.where.empty() ? "" : " WHERE " + c.where;
      const std::string and_where = c.where.empty() ? "" : " AND " + c.where;
      sql.push_back("UPDATE " + c.table + " SET " + c.column + " = " +
                    c.column + " + " + offset + where);
      sql.push_back(
          "UPDATE " + c.table + " SET " + c.column + " = (SELECT new_id FROM " +
          mapping + " WHERE old_id = " + c.table + "." + c.column + " - " +
          offset + ") WHERE " + c.column + " >= " + offset + and_where);
    }
  };
  // A table COLMAP has not created (no features written yet) holds no ids.
  images.erase(std::remove_if(images.begin(),
                              images.end(),
                              [&](const IdColumn& c) {
                                return !HasTable(db.get(), c.table);
                              }),
               images.end());
  renumber(images, "odomcal_image_ids");
  if (version.has_rigs_and_frames) {
    // Frames in the order of their first image (frames without one last).
    sql.push_back("DROP TABLE IF EXISTS temp.odomcal_frame_ids");
    sql.push_back(
        "CREATE TEMP TABLE odomcal_frame_ids AS SELECT frames.frame_id AS "
        "old_id, ROW_NUMBER() OVER (ORDER BY MIN(frame_data.data_id) IS NULL, "
        "MIN(frame_data.data_id), frames.frame_id) AS new_id FROM frames LEFT "
        "JOIN frame_data ON frame_data.frame_id = frames.frame_id AND "
        "frame_data.sensor_type = 0 GROUP BY frames.frame_id");
    renumber({{"frames", "frame_id", ""}, {"frame_data", "frame_id", ""}},
             "odomcal_frame_ids");
  }
  sql.push_back("COMMIT");
  for (const std::string& statement : sql) {
    if (sqlite3_exec(db.get(), statement.c_str(), nullptr, nullptr, nullptr) !=
        SQLITE_OK) {
      const std::string why = sqlite3_errmsg(db.get());
      sqlite3_exec(db.get(), "ROLLBACK", nullptr, nullptr, nullptr);
      throw FormatError(database_path + ": cannot renumber its images (" +
                        DescribeColmapDatabaseVersion(version) + "; " + why +
                        ")");
    }
  }
  return true;
}

}  // namespace odomcal
