// SqliteStore::Backup: a consistent copy of the live store (store.h). The database is copied by
// SQLite's online backup inside a read transaction of a connection of its own: one snapshot,
// while the store's writers go on (WAL). The frames file's size is read once that snapshot is
// open: every chunk the snapshot refers to was appended before its row committed, so it lies
// below that size. Chunks deleted during the copy keep their bytes until the copy is done.
#include <sqlite3.h>

#include <chrono>
#include <filesystem>
#include <system_error>

#include "server/store/sparse_copy.h"
#include "server/store/sqlite_error.h"
#include "server/store/sqlite_store.h"
#include "server/store/store_impl.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

namespace fs = std::filesystem;

// `dir` made and checked empty; its absolute path.
fs::path PrepareBackupDirectory(const std::string& dir) {
  if (dir.empty()) throw InputError("a backup needs a directory to write to");
  std::error_code error;
  const fs::path path = fs::absolute(dir, error);
  fs::create_directories(path, error);
  if (error || !fs::is_directory(path, error)) {
    throw InputError("cannot create the backup directory " + path.string() + ": " +
                     (error ? error.message() : "a file of that name exists"));
  }
  if (!fs::is_empty(path, error)) {
    throw InputError("the backup directory " + path.string() +
                     " is not empty: give a new or empty directory (a backup never overwrites)");
  }
  return path;
}

// Copies the database open in `source` (inside its read transaction) into a new file `to`.
void CopyDatabase(SqliteConnection& source, const std::string& to) {
  SqliteConnection target = SqliteConnection::Open(to);
  sqlite3_backup* backup = sqlite3_backup_init(target.get(), "main", source.get(), "main");
  if (backup == nullptr) {
    ThrowSqliteError(target.get(), sqlite3_errcode(target.get()), to, "start the backup");
  }
  const int step = sqlite3_backup_step(backup, -1);  // every page, in one snapshot
  const int finish = sqlite3_backup_finish(backup);
  if (step != SQLITE_DONE) ThrowSqliteError(target.get(), step, to, "copy the database");
  if (finish != SQLITE_OK) ThrowSqliteError(target.get(), finish, to, "finish the backup");
}

int64_t CountRuns(SqliteConnection& connection) {
  SqliteStatement count(connection, "SELECT count(*) FROM runs", "count the runs to back up");
  return count.Step() ? count.ColumnInt64(0) : 0;
}

}  // namespace

void ReleaseFramesLocked(SqliteStore::Impl& impl, const std::vector<FrameExtent>& extents) {
  if (impl.backups > 0) {
    impl.deferred_releases.insert(impl.deferred_releases.end(), extents.begin(), extents.end());
    return;
  }
  for (const FrameExtent& extent : extents) impl.frames.Release(extent.offset, extent.bytes);
}

StoreBackup SqliteStore::Backup(const std::string& dir) {
  const fs::path target = PrepareBackupDirectory(dir);
  {
    std::lock_guard lock(impl_->mutex);
    ++impl_->backups;
  }
  struct EndBackup {  // the releases held back, once no backup needs them
    Impl& impl;
    ~EndBackup() {
      std::lock_guard lock(impl.mutex);
      if (--impl.backups > 0) return;
      std::vector<FrameExtent> extents;
      extents.swap(impl.deferred_releases);
      ReleaseFramesLocked(impl, extents);
    }
  } end_backup{*impl_};

  StoreBackup result;
  result.dir = target.string();
  const std::string database = (target / kFileName).string();
  const std::string frames = (target / kFramesFileName).string();
  try {
    SqliteConnection source = SqliteConnection::Open(path());
    source.SetBusyTimeout(5000);
    source.Exec("BEGIN", "start the backup's read transaction");
    result.runs = CountRuns(source);  // the snapshot starts here
    result.frames_bytes = impl_->frames.end();
    CopyDatabase(source, database);
    source.Exec("COMMIT", "end the backup's read transaction");
    CopySparse(impl_->frames.path(), frames, result.frames_bytes);
    SyncPath(database);
    SyncPath(target.string());
  } catch (...) {
    std::error_code ignored;
    for (const std::string& file : {database, database + "-journal", database + "-wal", frames}) {
      fs::remove(file, ignored);
    }
    throw;
  }
  std::error_code error;
  result.database_bytes = static_cast<int64_t>(fs::file_size(database, error));
  return result;
}

}  // namespace mbstream
