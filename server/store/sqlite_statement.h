// RAII owner of one prepared SQLite statement (sqlite3_stmt*), with typed binds and columns.
// Parameter indexes start at 1 and column indexes at 0, as in SQLite.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

struct sqlite3_stmt;

namespace mbstream {

class SqliteConnection;

class SqliteStatement {
 public:
  // Prepares `sql` once for repeated use on `connection`, which must outlive the statement.
  // `operation` names the statement in errors (e.g. "insert run").
  SqliteStatement(SqliteConnection& connection, const std::string& sql, std::string operation);
  SqliteStatement(SqliteStatement&& other) noexcept;
  SqliteStatement& operator=(SqliteStatement&&) = delete;
  SqliteStatement(const SqliteStatement&) = delete;
  SqliteStatement& operator=(const SqliteStatement&) = delete;
  ~SqliteStatement();

  void BindInt64(int index, int64_t value);
  // Text is copied by SQLite.
  void BindText(int index, std::string_view value);
  // The blob is NOT copied: `value` must stay alive until the statement is reset.
  void BindBlob(int index, std::string_view value);

  // Advances to the next row: true when a row is available, false when done. Throws
  // SqliteError naming the operation.
  bool Step();
  // Steps a statement that returns no rows (INSERT, UPDATE, DELETE) to completion.
  void Run();

  int64_t ColumnInt64(int column) const;
  bool ColumnIsNull(int column) const;
  // Views into SQLite's memory: valid until the next Step or Reset.
  std::string_view ColumnText(int column) const;
  std::string_view ColumnBlob(int column) const;

  // Resets the statement for the next use and clears its bindings. Never throws (the error
  // of a failed step was already reported by Step).
  void Reset() noexcept;

 private:
  SqliteConnection* connection_;
  sqlite3_stmt* stmt_ = nullptr;
  std::string operation_;
};

// Resets a statement when leaving scope, so that a statement interrupted by an exception
// does not keep its read snapshot (and bound blobs) alive.
class ResetOnExit {
 public:
  explicit ResetOnExit(SqliteStatement& statement) : statement_(statement) {}
  ResetOnExit(const ResetOnExit&) = delete;
  ResetOnExit& operator=(const ResetOnExit&) = delete;
  ~ResetOnExit() { statement_.Reset(); }

 private:
  SqliteStatement& statement_;
};

}  // namespace mbstream
