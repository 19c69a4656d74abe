// Store's private state: the connection, its mutex and the prepared statements. Shared by
// the store_*.cc files, which implement one group of Store's methods each.
#pragma once

#include <cstdint>
#include <mutex>
#include <string>
#include <string_view>

#include <google/protobuf/message_lite.h>

#include "server/store/sqlite_connection.h"
#include "server/store/sqlite_statement.h"
#include "server/store/store.h"

namespace mbstream {

struct Store::Impl {
  explicit Impl(SqliteConnection connection);

  std::mutex mutex;  // guards everything below
  SqliteConnection db;

  SqliteStatement insert_model;
  SqliteStatement insert_asset;
  SqliteStatement select_model_infos;
  SqliteStatement select_model_bundle;
  SqliteStatement select_model_assets;
  SqliteStatement select_model_asset_names;
  SqliteStatement select_model_bytes;

  SqliteStatement upsert_run;
  SqliteStatement select_run;
  SqliteStatement select_runs;
  SqliteStatement select_unfinished_runs;

  SqliteStatement delete_frame_chunks;
  SqliteStatement delete_frame_chunks_after;
  SqliteStatement insert_frame_chunk;
  SqliteStatement select_frame_chunk;

  SqliteStatement upsert_probe;
  SqliteStatement select_probes;
};

// Milliseconds since the Unix epoch, from the system clock.
int64_t UnixNowMs();

// Serializes `message` for a blob column; throws InternalError when it cannot (a message over
// protobuf's 2 GB limit).
std::string SerializeForStore(const google::protobuf::MessageLite& message, std::string_view what);

// Parses a blob column into `message`; throws InternalError naming `what` (e.g. "run r-1")
// and the database when the stored bytes are corrupt.
void ParseFromStore(std::string_view bytes, google::protobuf::MessageLite& message,
                    std::string_view what, const std::string& path);

// Writes the run row (insert, or update keeping the row's order and its frames). The caller
// holds the mutex.
void UpsertRunLocked(Store::Impl& impl, const v1::RunInfo& info);

}  // namespace mbstream
