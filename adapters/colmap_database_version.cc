// Reads PRAGMA user_version, PRAGMA table_info of images and pose_priors,
// and which tables exist; colmap_database_version.h says what each layout
// means.
#include "odomcal/adapters/colmap_database_version.h"

#include "odomcal/adapters/colmap_database_internal.h"

#include <set>
#include <string>

namespace odomcal {
namespace {

using internal::NextRow;
using internal::Prepare;
using internal::StatementHandle;

constexpr int64_t kFirstVersion4 = 4000000;

std::set<std::string> Tables(sqlite3* database, const std::string& path) {
  const StatementHandle statement =
      Prepare(database,
              path,
              "SELECT name FROM sqlite_master WHERE type = 'table'",
              "sqlite_master");
  std::set<std::string> tables;
  while (NextRow(database, statement.get(), path)) {
    const unsigned char* name = sqlite3_column_text(statement.get(), 0);
    if (name != nullptr) tables.insert(reinterpret_cast<const char*>(name));
  }
  return tables;
}

// Column names of `table` (one of the fixed names above, never user text).
std::set<std::string> Columns(sqlite3* database,
                              const std::string& path,
                              const std::string& table) {
  const std::string sql = "PRAGMA table_info(" + table + ")";
  const StatementHandle statement =
      Prepare(database, path, sql.c_str(), table.c_str());
  std::set<std::string> columns;
  while (NextRow(database, statement.get(), path)) {
    const unsigned char* name = sqlite3_column_text(statement.get(), 1);
    if (name != nullptr) columns.insert(reinterpret_cast<const char*>(name));
  }
  return columns;
}

int64_t UserVersion(sqlite3* database, const std::string& path) {
  const StatementHandle statement =
      Prepare(database, path, "PRAGMA user_version", "user_version");
  return NextRow(database, statement.get(), path)
             ? sqlite3_column_int64(statement.get(), 0)
             : 0;
}

std::string Version4Label(int64_t user_version) {
  const int64_t major = user_version / 1000000;
  const int64_t minor = user_version / 10000 % 100;
  const int64_t patch = user_version / 100 % 100;
  return std::to_string(major) + "." + std::to_string(minor) + "." +
         std::to_string(patch);
}

}  // namespace

namespace internal {

ColmapDatabaseVersion InspectColmapDatabase(sqlite3* database,
                                            const std::string& path) {
  ColmapDatabaseVersion version;
  version.user_version = UserVersion(database, path);
  const std::set<std::string> tables = Tables(database, path);
  version.has_cameras_and_images =
      tables.count("cameras") != 0 && tables.count("images") != 0;
  version.has_rigs_and_frames =
      tables.count("rigs") != 0 && tables.count("frames") != 0;
  const std::set<std::string> image_columns =
      tables.count("images") != 0 ? Columns(database, path, "images")
                                  : std::set<std::string>();
  const bool image_priors = image_columns.count("prior_tx") != 0 &&
                            image_columns.count("prior_ty") != 0 &&
                            image_columns.count("prior_tz") != 0;
  std::string schema_label = "unknown";
  if (tables.count("pose_priors") != 0) {
    // The newer COLMAP that added pose_priors reads only that table.
    const std::set<std::string> columns =
        Columns(database, path, "pose_priors");
    const auto has = [&](const char* name) { return columns.count(name) != 0; };
    if (has("corr_data_id") && has("corr_sensor_id") &&
        has("corr_sensor_type") && has("position") &&
        has("position_covariance") && has("coordinate_system") &&
        has("gravity") && has("pose_prior_id")) {
      version.prior_layout = ColmapPriorLayout::kPosePriorsBySensor;
      schema_label = "4.x";
    } else if (has("image_id") && has("position") && has("coordinate_system")) {
      version.prior_layout = has("position_covariance")
                                 ? ColmapPriorLayout::kPosePriorsWithCovariance
                                 : ColmapPriorLayout::kPosePriorsByImage;
      schema_label = version.has_rigs_and_frames  ? "3.12 or 3.13"
                     : has("position_covariance") ? "3.11"
                                                  : "3.10";
    }
  } else if (image_priors) {
    version.prior_layout = ColmapPriorLayout::kImagesPriorColumns;
    schema_label = version.user_version == 3800   ? "3.8"
                   : version.user_version == 3900 ? "3.9"
                                                  : "3.8 or 3.9";
  }
  version.label = version.user_version >= kFirstVersion4
                      ? Version4Label(version.user_version)
                      : schema_label;
  if (!version.has_cameras_and_images) version.label = "unknown";
  return version;
}

}  // namespace internal

ColmapDatabaseVersion ReadColmapDatabaseVersion(
    const std::string& database_path) {
  const internal::DatabaseHandle database =
      internal::OpenReadOnly(database_path);
  return internal::InspectColmapDatabase(database.get(), database_path);
}

std::string DescribeColmapDatabaseVersion(
    const ColmapDatabaseVersion& version) {
  return (version.label == "unknown" ? std::string("an unknown COLMAP layout")
                                     : "COLMAP " + version.label) +
         ", user_version " + std::to_string(version.user_version);
}

}  // namespace odomcal
