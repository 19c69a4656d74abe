#include "server/store/sqlite_connection.h"

#include <utility>

#include <sqlite3.h>

#include "server/store/sqlite_error.h"

namespace mbstream {

SqliteConnection SqliteConnection::Open(const std::string& path) {
  sqlite3* db = nullptr;
  const int rc = sqlite3_open_v2(
      path.c_str(), &db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX, nullptr);
  if (rc != SQLITE_OK) {
    // sqlite3_open_v2 may hand back a handle even on failure; it must be closed.
    SqliteConnection owner(db, path);
    ThrowSqliteError(db, rc, path, "open database");
  }
  sqlite3_extended_result_codes(db, 1);
  return SqliteConnection(db, path);
}

SqliteConnection::SqliteConnection(SqliteConnection&& other) noexcept
    : db_(std::exchange(other.db_, nullptr)), path_(std::move(other.path_)) {}

SqliteConnection& SqliteConnection::operator=(SqliteConnection&& other) noexcept {
  if (this != &other) {
    if (db_ != nullptr) sqlite3_close_v2(db_);
    db_ = std::exchange(other.db_, nullptr);
    path_ = std::move(other.path_);
  }
  return *this;
}

SqliteConnection::~SqliteConnection() {
  // close_v2 defers the close until every statement of this connection is finalized, so the
  // order in which owners are destroyed does not matter.
  if (db_ != nullptr) sqlite3_close_v2(db_);
}

void SqliteConnection::Exec(const std::string& sql, const std::string& operation) {
  const int rc = sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, nullptr);
  if (rc != SQLITE_OK) ThrowSqliteError(db_, rc, path_, operation);
}

void SqliteConnection::SetBusyTimeout(int milliseconds) { sqlite3_busy_timeout(db_, milliseconds); }

int64_t SqliteConnection::Changes() const { return sqlite3_changes64(db_); }

}  // namespace mbstream
