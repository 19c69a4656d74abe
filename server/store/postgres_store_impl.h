// PostgresStore's private state: the connection, its mutex, and how each call runs in one
// transaction with the driver's failures turned into PostgresError. Shared by the
// postgres_store*.cc files.
#pragma once

#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

#include <pqxx/pqxx>

#include "server/store/kept_frames.h"
#include "server/store/postgres_error.h"
#include "server/store/postgres_store.h"
#include "server/store/store_codec.h"

namespace mbstream {

struct PostgresStore::Impl {
  Impl(std::string location, std::unique_ptr<pqxx::connection> connection);

  // Runs `body(transaction)` in one transaction under the mutex and commits it; a driver
  // failure (SQL error, lost connection) becomes a PostgresError naming `operation`.
  template <typename Body>
  auto Transact(const std::string& operation, Body&& body) {
    std::lock_guard lock(mutex);
    try {
      pqxx::work transaction(*db);
      if constexpr (std::is_void_v<decltype(body(transaction))>) {
        body(transaction);
        transaction.commit();
      } else {
        auto result = body(transaction);
        transaction.commit();
        return result;
      }
    } catch (const pqxx::broken_connection& error) {
      ThrowPostgresError(location, operation, error.what(), true);
    } catch (const pqxx::pqxx_exception& error) {
      ThrowPostgresError(location, operation, error.base().what(), false);
    }
  }

  const std::string location;  // the URI without password, for messages
  std::mutex mutex;            // guards db
  std::unique_ptr<pqxx::connection> db;
};

// A bytea field's bytes (libpqxx unescapes the text form into `holder`).
inline std::string_view BlobOf(const pqxx::field& field, pqxx::binarystring& holder) {
  holder = pqxx::binarystring(field);
  return {holder.get(), holder.size()};
}

// A bytea parameter (sent in binary form).
inline pqxx::binarystring BlobParam(const std::string& bytes) { return pqxx::binarystring(bytes); }

// The run of a row (info, keep, sweep_cancelled) of select_run, select_runs or
// kSelectSweepRunsSql; `blob` holds the info's unescaped bytes.
void ReadRunRow(const pqxx::row& row, pqxx::binarystring& blob, v1::RunInfo& info,
                const std::string& location);

// Writes the run row (insert, or update keeping its order and its frames).
void UpsertRun(pqxx::transaction_base& transaction, const v1::RunInfo& info);
// Inserts a new run row; false (nothing written) when its id is taken.
bool InsertNewRun(pqxx::transaction_base& transaction, const v1::RunInfo& info);

// What the run's stored frames are (kept_frames.h); a corrupt last chunk is removed, then the
// one before it is looked at. In the transaction that marks the run INTERRUPTED.
KeptFrames KeptFramesOf(pqxx::transaction_base& transaction, const std::string& run_id);

// Whether `holder` holds the lease of RUNNING run `run_id`; locks the row (FOR UPDATE).
bool HoldsLease(pqxx::transaction_base& transaction, const std::string& run_id,
                const std::string& holder);

}  // namespace mbstream
