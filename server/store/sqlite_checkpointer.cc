#include "server/store/sqlite_checkpointer.h"

#include <sqlite3.h>

#include <algorithm>
#include <exception>
#include <utility>

#include "server/store/sqlite_statement.h"

namespace mbstream {

SqliteCheckpointer::SqliteCheckpointer(SqliteConnection& writer, std::function<void()> before)
    : before_(std::move(before)), writer_(writer), own_(SqliteConnection::Open(writer.path())) {
  // A connection checkpoints only a database it has seen in WAL mode (else: a no-op).
  own_.Exec("PRAGMA journal_mode = WAL", "open the checkpointer's connection");
  SqliteStatement page_size(own_, "PRAGMA page_size", "read the page size");
  const int64_t page_bytes =
      page_size.Step() ? std::max<int64_t>(page_size.ColumnInt64(0), 512) : 4096;
  page_size.Reset();
  background_pages_ = static_cast<int>(kBackgroundBytes / page_bytes);
  backstop_pages_ = static_cast<int>(kBackstopBytes / page_bytes);
  next_ask_pages_ = background_pages_;
  thread_ = std::thread([this] { Loop(); });
  sqlite3_wal_hook(writer_.get(), &SqliteCheckpointer::OnCommit, this);
}

SqliteCheckpointer::~SqliteCheckpointer() {
  sqlite3_wal_hook(writer_.get(), nullptr, nullptr);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

int SqliteCheckpointer::OnCommit(void* self, sqlite3* db, const char* schema, int wal_pages) {
  auto* checkpointer = static_cast<SqliteCheckpointer*>(self);
  // Called on the writer's thread only (its connection is used by one thread at a time).
  if (wal_pages < checkpointer->last_wal_pages_) {  // the WAL started again from its beginning
    checkpointer->next_ask_pages_ = checkpointer->background_pages_;
  }
  checkpointer->last_wal_pages_ = wal_pages;
  if (wal_pages >= checkpointer->backstop_pages_) {
    // Behind: the writer copies what it can itself (PASSIVE, like SQLite's own; a failure
    // leaves the WAL as it is, for the next commit to try again).
    if (checkpointer->Before()) {
      sqlite3_wal_checkpoint_v2(db, schema, SQLITE_CHECKPOINT_PASSIVE, nullptr, nullptr);
    }
  } else if (wal_pages >= checkpointer->next_ask_pages_) {
    // Once per kBackgroundBytes of WAL: commits made while a checkpoint runs keep the WAL
    // from starting again, and asking at every one of them would checkpoint (and fdatasync)
    // after every commit.
    checkpointer->next_ask_pages_ = wal_pages + checkpointer->background_pages_;
    {
      std::lock_guard<std::mutex> lock(checkpointer->mutex_);
      checkpointer->asked_ = true;
    }
    checkpointer->wake_.notify_one();
  }
  return SQLITE_OK;
}

void SqliteCheckpointer::Loop() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    wake_.wait(lock, [&] { return stop_ || asked_; });
    if (stop_) return;
    asked_ = false;
    running_ = true;
    lock.unlock();
    // SQLITE_BUSY (the writer's backstop checkpoints meanwhile) or an I/O error: the WAL
    // stays as it is and the next commit past the threshold asks again.
    if (Before()) {
      sqlite3_wal_checkpoint_v2(own_.get(), "main", SQLITE_CHECKPOINT_PASSIVE, nullptr, nullptr);
    }
    lock.lock();
    running_ = false;
    ++done_;
    idle_.notify_all();
  }
}

bool SqliteCheckpointer::Before() const {
  if (!before_) return true;
  try {
    before_();
    return true;
  } catch (const std::exception&) {  // e.g. fdatasync failed: the WAL stays as it is
    return false;
  }
}

int64_t SqliteCheckpointer::WaitIdle() {
  std::unique_lock<std::mutex> lock(mutex_);
  idle_.wait(lock, [&] { return !asked_ && !running_; });
  return done_;
}

}  // namespace mbstream
