// RAII transaction: BEGIN IMMEDIATE on construction, ROLLBACK unless Commit() was called.
#pragma once

#include <string>

namespace mbstream {

class SqliteConnection;

class SqliteTransaction {
 public:
  // IMMEDIATE takes the write lock at once, so a transaction never fails half-way with
  // SQLITE_BUSY on its first write (the busy timeout applies to BEGIN instead).
  SqliteTransaction(SqliteConnection& connection, std::string operation);
  SqliteTransaction(const SqliteTransaction&) = delete;
  SqliteTransaction& operator=(const SqliteTransaction&) = delete;
  ~SqliteTransaction();

  void Commit();

 private:
  SqliteConnection& connection_;
  std::string operation_;
  bool open_ = true;
};

}  // namespace mbstream
