// One statement per layout of colmap_database_priors.h, run per image inside
// one transaction. The image is found by name inside the statement, so a
// name the database lacks changes nothing.
#include "odomcal/adapters/colmap_database_priors.h"

#include "odomcal/adapters/colmap_database_internal.h"
#include "odomcal/adapters/colmap_database_version.h"
#include "odomcal/adapters/format_error.h"

#include <sqlite3.h>

#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace odomcal {
namespace {

using internal::DatabaseHandle;
using internal::StatementHandle;

// Little-endian float64 values, as COLMAP's WriteStaticMatrixBlob stores an
// Eigen matrix (column major).
std::string DoubleBlob(const std::vector<double>& values) {
  std::string blob;
  for (const double value : values) {
    uint64_t bits = 0;
    std::memcpy(&bits, &value, sizeof(bits));
    for (int i = 0; i < 8; ++i) {
      blob.push_back(static_cast<char>((bits >> (8 * i)) & 0xff));
    }
  }
  return blob;
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The statements of a layout: ?1 = name, ?2 = position blob, ?3 = x, ?4 = y,
// ?5 = z, ?6 = 9 NaN blob, ?7 = 3 NaN blob. `clear` (may be empty) runs
// before `write`.
struct LayoutStatements {
  const char* clear = "";
  const char* write = "";
};

LayoutStatements StatementsOf(ColmapPriorLayout layout) {
  switch (layout) {
    case ColmapPriorLayout::kImagesPriorColumns:
      return {"",
              "UPDATE images SET prior_tx = ?3, prior_ty = ?4, prior_tz = ?5 "
              "WHERE name = ?1"};
    case ColmapPriorLayout::kPosePriorsByImage:
      return {"",
              "INSERT OR REPLACE INTO pose_priors (image_id, position, "
              "coordinate_system) SELECT image_id, ?2, 1 FROM images WHERE "
              "name = ?1"};
    case ColmapPriorLayout::kPosePriorsWithCovariance:
      return {"",
              "INSERT OR REPLACE INTO pose_priors (image_id, position, "
              "coordinate_system, position_covariance) SELECT image_id, ?2, "
              "1, ?6 FROM images WHERE name = ?1"};
    case ColmapPriorLayout::kPosePriorsBySensor:
      return {
          "DELETE FROM pose_priors WHERE corr_sensor_type = 0 AND "
          "corr_data_id IN (SELECT image_id FROM images WHERE name = ?1)",
          "INSERT INTO pose_priors (pose_prior_id, corr_data_id, "
          "corr_sensor_id, corr_sensor_type, position, "
          "position_covariance, coordinate_system, gravity) SELECT NULL, "
          "image_id, camera_id, 0, ?2, ?6, 1, ?7 FROM images WHERE name "
          "= ?1"};
    case ColmapPriorLayout::kNone:
      break;
  }
  return {};
}

}  // namespace

int WriteColmapDatabasePositionPriors(
    const std::string& database_path,
    const std::map<std::string, Eigen::Vector3d>& positions) {
  const DatabaseHandle db = internal::OpenReadWrite(database_path);
  const ColmapDatabaseVersion version =
      internal::InspectColmapDatabase(db.get(), database_path);
  const LayoutStatements sql = StatementsOf(version.prior_layout);
  if (!version.has_cameras_and_images ||
      version.prior_layout == ColmapPriorLayout::kNone) {
    throw FormatError(database_path +
                      ": cannot write position priors: the database (" +
                      DescribeColmapDatabaseVersion(version) +
                      ") has neither images.prior_tx/ty/tz (COLMAP 3.8, 3.9) "
                      "nor a pose_priors table of COLMAP 3.10 to 4.1");
  }
  const auto fail = [&](const std::string& what) {
    throw FormatError(database_path + ": " + what + " (" +
                      DescribeColmapDatabaseVersion(version) + "; " +
                      sqlite3_errmsg(db.get()) + ")");
  };
  const auto prepare = [&](const char* text) {
    sqlite3_stmt* statement = nullptr;
    if (*text != '\0' &&
        sqlite3_prepare_v2(db.get(), text, -1, &statement, nullptr) !=
            SQLITE_OK) {
      fail("cannot prepare the position priors' statement");
    }
    return StatementHandle(statement);
  };
  const StatementHandle clear = prepare(sql.clear);
  const StatementHandle write = prepare(sql.write);
  if (sqlite3_exec(db.get(), "BEGIN", nullptr, nullptr, nullptr) != SQLITE_OK) {
    fail("cannot begin a transaction");
  }
  const std::string covariance = DoubleBlob(std::vector<double>(9, kNaN));
  const std::string gravity = DoubleBlob(std::vector<double>(3, kNaN));
  int updated = 0;
  for (const auto& [name, position] : positions) {
    const std::string position_blob =
        DoubleBlob({position.x(), position.y(), position.z()});
    for (sqlite3_stmt* statement : {clear.get(), write.get()}) {
      if (statement == nullptr) continue;
      sqlite3_reset(statement);
      const int count = sqlite3_bind_parameter_count(statement);
      // Every statement uses ?1; the others are bound when present.
      sqlite3_bind_text(statement, 1, name.c_str(), -1, SQLITE_TRANSIENT);
      if (count >= 2) {
        sqlite3_bind_blob(statement,
                          2,
                          position_blob.data(),
                          static_cast<int>(position_blob.size()),
                          SQLITE_TRANSIENT);
      }
      if (count >= 5) {
        for (int k = 0; k < 3; ++k) {
          sqlite3_bind_double(statement, 3 + k, position[k]);
        }
      }
      if (count >= 6) {
        sqlite3_bind_blob(statement,
                          6,
                          covariance.data(),
                          static_cast<int>(covariance.size()),
                          SQLITE_TRANSIENT);
      }
      if (count >= 7) {
        sqlite3_bind_blob(statement,
                          7,
                          gravity.data(),
                          static_cast<int>(gravity.size()),
                          SQLITE_TRANSIENT);
      }
      if (sqlite3_step(statement) != SQLITE_DONE) {
        const std::string why = sqlite3_errmsg(db.get());
        sqlite3_exec(db.get(), "ROLLBACK", nullptr, nullptr, nullptr);
        throw FormatError(database_path +
                          ": cannot write the position prior of image " + name +
                          " (" + DescribeColmapDatabaseVersion(version) + "; " +
                          why + ")");
      }
    }
    updated += sqlite3_changes(db.get()) > 0 ? 1 : 0;
  }
  if (sqlite3_exec(db.get(), "COMMIT", nullptr, nullptr, nullptr) !=
      SQLITE_OK) {
    fail("cannot commit the priors");
  }
  return updated;
}

}  // namespace odomcal
