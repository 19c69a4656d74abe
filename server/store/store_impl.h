// SqliteStore's private state: the connection, its mutex and the prepared statements. Shared by
// the store_*.cc files, which implement one group of Store's methods each.
#pragma once

#include <cstdint>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "server/store/frame_file.h"
#include "server/store/kept_frames.h"
#include "server/store/sqlite_checkpointer.h"
#include "server/store/sqlite_connection.h"
#include "server/store/sqlite_statement.h"
#include "server/store/sqlite_store.h"
#include "server/store/store_codec.h"

namespace mbstream {

struct SqliteStore::Impl {
  Impl(SqliteConnection connection, const std::string& frames_path);

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
  SqliteStatement insert_new_run;  // nothing when the id is taken
  SqliteStatement select_run;
  SqliteStatement select_runs;
  SqliteStatement select_sweep_runs;  // store_sweeps.cc
  SqliteStatement count_sweep_runs;
  SqliteStatement select_sweep;
  SqliteStatement select_sweep_cancelled;
  SqliteStatement select_unfinished_runs;
  // The run queue (store_queue.cc): prepared once, used for every run.
  SqliteStatement select_oldest_queued_run;
  SqliteStatement select_run_lease;
  SqliteStatement update_run_lease;

  SqliteStatement delete_frame_chunks;
  SqliteStatement delete_frame_chunks_after;
  SqliteStatement insert_frame_chunk;
  SqliteStatement select_frame_chunk;

  SqliteStatement upsert_probe;
  SqliteStatement select_probes;

  FrameFile frames;  // every chunk's frames since schema version 5
  // Backups under way (store_backup.cc): while any is, the bytes of deleted chunks are not
  // released (a backup's database may still refer to them) but kept here until the last ends.
  int backups = 0;
  std::vector<FrameExtent> deferred_releases;

  // Last: unhooked from `db` before anything else is torn down.
  SqliteCheckpointer checkpointer;
};

// The run of a row of select_run, select_runs or select_sweep_runs (info, keep,
// sweep_cancelled). The caller holds the mutex.
void ReadRunRowLocked(const SqliteStore::Impl& impl, const SqliteStatement& row, v1::RunInfo& info);

// Writes the run row (insert, or update keeping the row's order and its frames). The caller
// holds the mutex.
void UpsertRunLocked(SqliteStore::Impl& impl, const v1::RunInfo& info);
// Inserts a new run row; false (nothing written) when its id is taken. The caller holds the
// mutex.
bool InsertNewRunLocked(SqliteStore::Impl& impl, const v1::RunInfo& info);

// What the run's stored frames are (kept_frames.h); a damaged last chunk (its bytes did not
// reach the disk) is removed, then the one before it is looked at. The caller holds the mutex,
// in the transaction that marks the run INTERRUPTED.
KeptFrames KeptFramesLocked(SqliteStore::Impl& impl, const std::string& run_id);

// At open: releases the frames file's gaps between referenced chunks (frame_file.h): bytes of
// chunks deleted or replaced. Returns how many bytes. The caller holds the mutex (or has the
// store to itself).
int64_t ReleaseUnreferencedFramesLocked(SqliteStore::Impl& impl);

// Releases `extents` of the frames file, or keeps them for later while a backup is under way
// (store_backup.cc). The caller holds the mutex.
void ReleaseFramesLocked(SqliteStore::Impl& impl, const std::vector<FrameExtent>& extents);

// Whether `holder` holds the lease of RUNNING run `run_id`. The caller holds the mutex.
bool HoldsLeaseLocked(SqliteStore::Impl& impl, const std::string& run_id,
                      const std::string& holder);

}  // namespace mbstream
