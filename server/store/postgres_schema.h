// The store's PostgreSQL schema, versioned (table mbstream_schema) and migrated forward only,
// like the SQLite one (store_schema.h) with the same tables and version numbers.
#pragma once

#include <string>

namespace pqxx {
class connection_base;
}

namespace mbstream {

// The schema version written by this build. Raise it with every schema change and add the
// step to kMigrations in postgres_schema.cc.
// 1: models, runs, frame chunks, probes. 2: the replays' probe sets. 3: the run queue's leases.
// 4-6 as in store_schema.h. 7: a run's sweep (runs.sweep_id, indexed; runs.sweep_cancelled).
inline constexpr int kPostgresSchemaVersion = 8;

// Creates the schema in an empty database, or migrates an mbstream database of an older
// version up to `target_version` (tests migrate to an older one to make a previous-version
// database), in one transaction under an advisory lock (servers starting together migrate
// once). Throws InputError naming `location` and what to do when the database holds another
// program's tables or has a newer version; pqxx exceptions for database failures.
void EnsurePostgresSchema(pqxx::connection_base& db, const std::string& location,
                          int target_version = kPostgresSchemaVersion);

}  // namespace mbstream
