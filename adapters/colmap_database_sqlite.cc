// The SQLite helpers of colmap_database_internal.h.
#include "odomcal/adapters/colmap_database_internal.h"
#include "odomcal/adapters/format_error.h"

#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>

namespace odomcal::internal {
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

}  // namespace

void FailDatabase(const std::string& path, const std::string& what) {
  throw FormatError(path + ": " + what);
}

DatabaseHandle OpenReadWrite(const std::string& path) {
  sqlite3* raw = nullptr;
  if (sqlite3_open_v2(path.c_str(), &raw, SQLITE_OPEN_READWRITE, nullptr) !=
      SQLITE_OK) {
    const std::string why = raw ? sqlite3_errmsg(raw) : "out of memory";
    sqlite3_close(raw);
    FailDatabase(path, "cannot open the database for writing (" + why + ")");
  }
  return DatabaseHandle(raw);
}

DatabaseHandle OpenReadOnly(const std::string& path) {
  std::error_code error;
  if (path.empty() || !fs::is_regular_file(path, error)) {
    FailDatabase(path,
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
    FailDatabase(
        path,
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
    FailDatabase(
        path,
        std::string("not a readable COLMAP database (reading table '") + table +
            "'): " + sqlite3_errmsg(database));
  }
  return statement;
}

bool NextRow(sqlite3* database,
             sqlite3_stmt* statement,
             const std::string& path) {
  const int status = sqlite3_step(statement);
  if (status == SQLITE_ROW) return true;
  if (status == SQLITE_DONE) return false;
  FailDatabase(path,
               std::string("cannot read the COLMAP database: ") +
                   sqlite3_errmsg(database));
}

}  // namespace odomcal::internal
