// SQLite access shared by the COLMAP database readers and writers
// (colmap_database.cc, colmap_database_version.cc,
// colmap_database_priors.cc); internal: not installed.
#pragma once

#include "odomcal/adapters/colmap_database_version.h"

#include <sqlite3.h>

#include <memory>
#include <string>

namespace odomcal::internal {

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

// Throws FormatError("path: what").
[[noreturn]] void FailDatabase(const std::string& path,
                               const std::string& what);

// Opens `path` through a percent-encoded "file:" URI with
// mode=ro&immutable=1 and SQLITE_OPEN_READONLY | SQLITE_OPEN_URI: no locks,
// no journal, the file stays byte-identical. Throws FormatError naming the
// path when it is missing, not a regular file or not an SQLite database.
DatabaseHandle OpenReadOnly(const std::string& path);

// Opens `path` for reading and writing (a database odomcal itself created:
// the workspace of `odomcal run`). Throws FormatError("path: cannot open the
// database for writing (why)").
DatabaseHandle OpenReadWrite(const std::string& path);

// Prepares `sql`; a failure throws FormatError naming the path and `table`.
StatementHandle Prepare(sqlite3* database,
                        const std::string& path,
                        const char* sql,
                        const char* table);

// Steps to the next row; false when done. Throws on SQLite errors.
bool NextRow(sqlite3* database,
             sqlite3_stmt* statement,
             const std::string& path);

// The schema of an open database (PRAGMA user_version, the tables and
// columns that tell the versions apart). Throws FormatError naming the path
// when the file is not an SQLite database.
ColmapDatabaseVersion InspectColmapDatabase(sqlite3* database,
                                            const std::string& path);

}  // namespace odomcal::internal
