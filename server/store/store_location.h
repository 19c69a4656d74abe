// Where the store is, as given to mbstream-server's --store (or --data): parsed and checked
// at the edge, then opened with OpenStore.
#pragma once

#include <memory>
#include <string>

#include "server/store/store.h"

namespace mbstream {

struct StoreLocation {
  enum class Kind { kSqlite, kPostgresql };
  Kind kind = Kind::kSqlite;
  // The SQLite data directory, or the PostgreSQL URI (never holding a password).
  std::string target;
  // PostgreSQL's password (from a file); empty = libpq's own lookup (PGPASSFILE, ~/.pgpass).
  std::string password;
};

// Parses `sqlite:DIRECTORY` or `postgresql://user@host:port/database` (also `postgres://`;
// a unix socket directory as host, percent-encoded). Throws InputError saying what --store
// takes when `text` is neither, and when the URI holds a password (it would show in the
// process list: use a password file or PGPASSFILE).
StoreLocation ParseStoreLocation(const std::string& text);

// The first line of `path` (the PostgreSQL password). Throws InputError naming the file when
// it cannot be read or is empty.
std::string ReadStorePasswordFile(const std::string& path);

// Opens the store at `location` (SqliteStore::Open or PostgresStore::Open).
std::unique_ptr<Store> OpenStore(const StoreLocation& location);

}  // namespace mbstream
