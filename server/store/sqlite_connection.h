// RAII owner of one SQLite connection (sqlite3*). sqlite3.h stays out of this header.
#pragma once

#include <cstdint>
#include <string>

struct sqlite3;

namespace mbstream {

class SqliteConnection {
 public:
  // Opens the database file at `path` read-write, creating it when missing. Throws
  // SqliteError. The connection has no mutex of its own (SQLITE_OPEN_NOMUTEX): its user
  // serialises access (Store holds one mutex).
  static SqliteConnection Open(const std::string& path);

  SqliteConnection(SqliteConnection&& other) noexcept;
  SqliteConnection& operator=(SqliteConnection&& other) noexcept;
  SqliteConnection(const SqliteConnection&) = delete;
  SqliteConnection& operator=(const SqliteConnection&) = delete;
  ~SqliteConnection();

  // Runs one or more SQL statements that return no rows needed by the caller (DDL,
  // BEGIN/COMMIT, PRAGMA assignments). `operation` names what it is for in errors.
  void Exec(const std::string& sql, const std::string& operation);

  // Waits up to `milliseconds` for a lock held by another connection before failing with
  // SQLITE_BUSY.
  void SetBusyTimeout(int milliseconds);

  // Rows changed by the latest INSERT/UPDATE/DELETE.
  int64_t Changes() const;

  sqlite3* get() const { return db_; }
  const std::string& path() const { return path_; }

 private:
  SqliteConnection(sqlite3* db, std::string path) : db_(db), path_(std::move(path)) {}

  sqlite3* db_ = nullptr;
  std::string path_;
};

}  // namespace mbstream
