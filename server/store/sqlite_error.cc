#include "server/store/sqlite_error.h"

#include <sqlite3.h>

#include "server/store/disk_full_error.h"

namespace mbstream {

void ThrowSqliteError(sqlite3* db, int rc, const std::string& path, const std::string& operation) {
  // sqlite3_errmsg describes the latest failure on `db`, which is more specific than the
  // generic text of the result code (e.g. "UNIQUE constraint failed: runs.id").
  std::string detail = db != nullptr ? sqlite3_errmsg(db) : sqlite3_errstr(rc);
  std::string message = "store " + path + ": " + operation + " failed: " + detail +
                        " (SQLite result code " + std::to_string(rc) + ")";
  switch (rc & 0xff) {
    case SQLITE_FULL:  // an operating condition, not a bug: RESOURCE_EXHAUSTED
      throw DiskFullError(message + "; " + kDiskFullAdvice);
    case SQLITE_READONLY:
    case SQLITE_PERM:
      message += "; the data directory or database file is not writable: fix its permissions";
      break;
    case SQLITE_BUSY:
    case SQLITE_LOCKED:
      message += "; another process holds the database: is a second server using this --data?";
      break;
    default:
      break;
  }
  throw SqliteError(rc, message);
}

}  // namespace mbstream
