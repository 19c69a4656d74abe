// Checkpoints a WAL database on a thread of its own, so that a commit never waits for the
// copy of the WAL into the database file and its fdatasyncs. SQLite's automatic checkpoint
// runs inside the commit that crosses its threshold: with one store lock, every run's store
// call waited for it (a run's 84 KB of frames fills the default 1,000-page WAL every ~40
// runs; docs/performance.md).
//
// The writer's connection gets a WAL hook instead of the automatic checkpoint: from
// kBackgroundBytes of WAL on, a commit wakes the checkpointer, which checkpoints PASSIVE on a
// connection of its own (it never blocks a writer or a reader; the next write after a
// complete checkpoint starts the WAL from its beginning again). From kBackstopBytes on (the
// checkpointer fell behind, e.g. behind a long reader) the committing writer checkpoints
// itself, as SQLite's own automatic checkpoint would.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>

#include "server/store/sqlite_connection.h"

namespace mbstream {

class SqliteCheckpointer {
 public:
  // In bytes of WAL, turned into pages of the database's page size: SQLite's default
  // automatic checkpoint (1,000 pages of 4 KB), and 16 times that.
  static constexpr int64_t kBackgroundBytes = 1000 * 4096;
  static constexpr int64_t kBackstopBytes = 16 * kBackgroundBytes;

  // Hooks into `writer` (which must outlive this) and opens a connection of its own to the
  // same file. Throws SqliteError when that connection cannot be opened. `before` (if any)
  // runs before each checkpoint (the store makes its frames file durable there, frame_file.h);
  // when it throws, that checkpoint is skipped.
  explicit SqliteCheckpointer(SqliteConnection& writer, std::function<void()> before = {});
  ~SqliteCheckpointer();  // unhooks, then stops and joins the thread
  SqliteCheckpointer(const SqliteCheckpointer&) = delete;
  SqliteCheckpointer& operator=(const SqliteCheckpointer&) = delete;

  // Waits until no checkpoint is asked for or running (tests); returns the checkpoints
  // completed so far on the thread.
  int64_t WaitIdle();

 private:
  static int OnCommit(void* self, struct sqlite3* db, const char* schema, int wal_pages);
  void Loop();
  bool Before() const;  // runs before_; false when it threw

  std::function<void()> before_;
  SqliteConnection& writer_;
  SqliteConnection own_;
  // The writer's thread only (OnCommit): the WAL's size at the last commit, and the size
  // from which the next checkpoint is asked for.
  int background_pages_;  // kBackgroundBytes and kBackstopBytes in pages
  int backstop_pages_;
  int last_wal_pages_ = 0;
  int next_ask_pages_;
  std::mutex mutex_;
  std::condition_variable wake_;  // a checkpoint asked for, or stop
  std::condition_variable idle_;  // a checkpoint done
  bool asked_ = false;
  bool running_ = false;
  bool stop_ = false;
  int64_t done_ = 0;
  std::thread thread_;
};

}  // namespace mbstream
