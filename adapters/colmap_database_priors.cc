#include "odomcal/adapters/colmap_database_priors.h"

#include "odomcal/adapters/format_error.h"

#include <sqlite3.h>

#include <memory>

namespace odomcal {
namespace {

struct DatabaseCloser {
  void operator()(sqlite3* db) const { sqlite3_close(db); }
};
struct StatementFinalizer {
  void operator()(sqlite3_stmt* statement) const {
    sqlite3_finalize(statement);
  }
};

}  // namespace

int WriteColmapDatabasePositionPriors(
    const std::string& database_path,
    const std::map<std::string, Eigen::Vector3d>& positions) {
  sqlite3* raw = nullptr;
  if (sqlite3_open_v2(
          database_path.c_str(), &raw, SQLITE_OPEN_READWRITE, nullptr) !=
      SQLITE_OK) {
    const std::string why = raw ? sqlite3_errmsg(raw) : "out of memory";
    sqlite3_close(raw);
    throw FormatError(database_path +
                      ": cannot open the database for writing (" + why + ")");
  }
  std::unique_ptr<sqlite3, DatabaseCloser> db(raw);
  auto fail = [&](const std::string& what) {
    throw FormatError(database_path + ": " + what + " (" +
                      sqlite3_errmsg(db.get()) + ")");
  };
  sqlite3_stmt* raw_statement = nullptr;
  if (sqlite3_prepare_v2(db.get(),
                         "UPDATE images SET prior_tx = ?1, prior_ty = ?2, "
                         "prior_tz = ?3 WHERE name = ?4",
                         -1,
                         &raw_statement,
                         nullptr) != SQLITE_OK) {
    fail("no images.prior_tx/ty/tz columns (COLMAP 3.8 schema expected)");
  }
  std::unique_ptr<sqlite3_stmt, StatementFinalizer> statement(raw_statement);
  if (sqlite3_exec(db.get(), "BEGIN", nullptr, nullptr, nullptr) != SQLITE_OK) {
    fail("cannot begin a transaction");
  }
  int updated = 0;
  for (const auto& [name, position] : positions) {
    sqlite3_reset(statement.get());
    sqlite3_bind_double(statement.get(), 1, position.x());
    sqlite3_bind_double(statement.get(), 2, position.y());
    sqlite3_bind_double(statement.get(), 3, position.z());
    sqlite3_bind_text(statement.get(), 4, name.c_str(), -1, SQLITE_TRANSIENT);
    if (sqlite3_step(statement.get()) != SQLITE_DONE) {
      sqlite3_exec(db.get(), "ROLLBACK", nullptr, nullptr, nullptr);
      fail("cannot update the prior of image " + name);
    }
    updated += sqlite3_changes(db.get());
  }
  if (sqlite3_exec(db.get(), "COMMIT", nullptr, nullptr, nullptr) !=
      SQLITE_OK) {
    fail("cannot commit the priors");
  }
  return updated;
}

}  // namespace odomcal
