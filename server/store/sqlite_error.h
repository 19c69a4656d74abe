// The exception for SQLite failures at runtime, carrying SQLite's result code.
#pragma once

#include <string>

#include "shared/common/check.h"

struct sqlite3;

namespace mbstream {

// A SQLite call failed. It is an InternalError (the service reports it as an internal
// failure); `code()` is SQLite's (extended) result code so that callers such as Store::Open
// can turn specific failures (SQLITE_NOTADB, SQLITE_CANTOPEN) into an InputError.
class SqliteError : public InternalError {
 public:
  SqliteError(int code, const std::string& message) : InternalError(message), code_(code) {}
  int code() const { return code_; }

 private:
  int code_;
};

// Throws SqliteError for result code `rc` of `operation` (e.g. "insert run r-1") on the
// database at `path`, with SQLite's own message from `db` (which may be null).
// SQLITE_FULL throws DiskFullError (disk_full_error.h) instead.
[[noreturn]] void ThrowSqliteError(sqlite3* db, int rc, const std::string& path,
                                   const std::string& operation);

}  // namespace mbstream
