// The SQLite implementation of Store: one file, <data directory>/mbstream.sqlite3, WAL
// journal, one mutex around one connection. Runtime SQLite failures throw SqliteError (an
// InternalError) naming the operation and SQLite's message.
#pragma once

#include <memory>
#include <string>

#include "server/store/store.h"
#include "server/store/store_methods.h"

namespace mbstream {

class SqliteStore final : public Store {
 public:
  // Opens or creates <directory>/mbstream.sqlite3 (creating the directory). WAL journal,
  // foreign keys on, busy timeout. Throws InputError naming the path and what to do when the
  // directory cannot be created or the file is not an mbstream database (or has a newer
  // schema version, PRAGMA user_version).
  static std::unique_ptr<SqliteStore> Open(const std::string& directory);
  ~SqliteStore() override;

  MBSTREAM_STORE_OVERRIDES  // store_methods.h: every method of Store

  // Private state, opaque here (defined in store_impl.h for the store's own .cc files).
  struct Impl;

 private:
  explicit SqliteStore(std::unique_ptr<Impl> impl);

  std::unique_ptr<Impl> impl_;
};

}  // namespace mbstream
