// The PostgreSQL implementation of Store (through libpqxx): several servers share one
// database. The same contracts as PostgresStore; one mutex around one connection per store,
// one transaction per call; frames in chunk blobs, probe reports in multi-row inserts.
// Runtime failures throw PostgresError (an InternalError) naming the database, the operation
// and PostgreSQL's message.
#pragma once

#include <memory>
#include <string>

#include "server/store/store.h"
#include "server/store/store_methods.h"

namespace mbstream {

class PostgresStore final : public Store {
 public:
  // Connects to `uri` (postgresql://user@host:port/database, no password in it) with
  // `password` (empty: libpq's own, PGPASSFILE or ~/.pgpass) and creates or migrates the
  // schema (postgres_schema.h). Throws InputError naming the URI and what to do when the
  // database cannot be reached or used (refused, authentication, another program's tables,
  // a newer schema version).
  static std::unique_ptr<PostgresStore> Open(const std::string& uri, const std::string& password);
  ~PostgresStore() override;

  MBSTREAM_STORE_OVERRIDES  // store_methods.h: every method of Store

  // Private state, opaque here (defined in postgres_store_impl.h for the store's own .cc
  // files).
  struct Impl;

 private:
  explicit PostgresStore(std::unique_ptr<Impl> impl);

  std::unique_ptr<Impl> impl_;
};

}  // namespace mbstream
