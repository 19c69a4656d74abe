// SqliteStore: the run queue (claims, leases, expiry), each call one BEGIN IMMEDIATE
// transaction (sqlite_transaction.h), which has the write lock from its start: the same
// semantics as PostgreSQL's SELECT ... FOR UPDATE SKIP LOCKED for the one writer SQLite has.
#include "server/store/sqlite_store.h"
#include "server/store/sqlite_transaction.h"
#include "server/store/store_impl.h"

namespace mbstream {
namespace {

void SetLease(SqliteStore::Impl& impl, const std::string& run_id, const std::string* holder,
              int64_t expires_unix_ms) {
  SqliteStatement& update = impl.update_run_lease;
  ResetOnExit reset(update);
  update.BindText(1, run_id);
  if (holder != nullptr) update.BindText(2, *holder);
  update.BindInt64(3, expires_unix_ms);
  update.Run();
}

// The infos of the rows `select` selects (its first column), with `bind` applied first.
template <typename Bind>
std::vector<v1::RunInfo> SelectRuns(SqliteStore::Impl& impl, SqliteStatement& select,
                                    const char* what, Bind bind) {
  std::vector<v1::RunInfo> runs;
  ResetOnExit reset(select);
  bind(select);
  while (select.Step()) {
    ParseFromStore(select.ColumnBlob(0), runs.emplace_back(), what, impl.db.path());
  }
  return runs;
}

}  // namespace

bool HoldsLeaseLocked(SqliteStore::Impl& impl, const std::string& run_id,
                      const std::string& holder) {
  SqliteStatement& select = impl.select_run_lease;
  ResetOnExit reset(select);
  select.BindText(1, run_id);
  select.BindInt64(2, v1::RUNNING);
  select.BindText(3, holder);
  return select.Step();
}

std::optional<v1::RunInfo> SqliteStore::ClaimQueuedRun(const RunLease& lease) {
  std::lock_guard lock(impl_->mutex);
  SqliteTransaction transaction(impl_->db, "claim a queued run");
  std::vector<v1::RunInfo> oldest =
      SelectRuns(*impl_, impl_->select_oldest_queued_run, "claim a queued run",
                 [](SqliteStatement& s) { s.BindInt64(1, v1::QUEUED); });
  if (oldest.empty()) return std::nullopt;
  v1::RunInfo& info = oldest.front();
  ApplyClaim(info, lease);
  UpsertRunLocked(*impl_, info);
  const std::string holder = LeaseHolder(info);
  SetLease(*impl_, info.id(), &holder, lease.expires_unix_ms);
  transaction.Commit();
  return info;
}

bool SqliteStore::RenewLease(const std::string& run_id, const std::string& holder,
                             int64_t expires_unix_ms) {
  std::lock_guard lock(impl_->mutex);
  SqliteTransaction transaction(impl_->db, "renew a run lease");
  if (!HoldsLeaseLocked(*impl_, run_id, holder)) return false;
  SetLease(*impl_, run_id, &holder, expires_unix_ms);
  transaction.Commit();
  return true;
}

std::vector<v1::RunInfo> SqliteStore::ReapExpiredLeases(int64_t now_unix_ms,
                                                        const std::string& reaper) {
  std::lock_guard lock(impl_->mutex);
  SqliteTransaction transaction(impl_->db, "reap expired run leases");
  SqliteStatement select(
      impl_->db,
      "SELECT info FROM runs WHERE state = ?1 AND lease_expires_unix_ms < ?2 ORDER BY ord",
      "reap expired run leases");
  std::vector<v1::RunInfo> expired =
      SelectRuns(*impl_, select, "reap expired run leases", [&](SqliteStatement& s) {
        s.BindInt64(1, v1::RUNNING);
        s.BindInt64(2, now_unix_ms);
      });
  for (v1::RunInfo& info : expired) {
    if (ApplyLeaseExpired(info, now_unix_ms, reaper) == v1::INTERRUPTED) {
      ApplyKeptFrames(KeptFramesLocked(*impl_, info.id()), info);
    }
    UpsertRunLocked(*impl_, info);
    SetLease(*impl_, info.id(), nullptr, 0);
  }
  transaction.Commit();
  return expired;
}

std::vector<v1::RunInfo> SqliteStore::ListRunningRuns() const {
  std::lock_guard lock(impl_->mutex);
  SqliteStatement select(impl_->db, "SELECT info FROM runs WHERE state = ?1 ORDER BY ord",
                         "list running runs");
  return SelectRuns(*impl_, select, "list running runs",
                    [](SqliteStatement& s) { s.BindInt64(1, v1::RUNNING); });
}

bool SqliteStore::PutRunIfHeld(const v1::RunInfo& info, const std::string& holder) {
  std::lock_guard lock(impl_->mutex);
  SqliteTransaction transaction(impl_->db, "write run " + info.id());
  if (!HoldsLeaseLocked(*impl_, info.id(), holder)) return false;
  UpsertRunLocked(*impl_, info);
  SetLease(*impl_, info.id(), nullptr, 0);
  transaction.Commit();
  return true;
}

std::optional<v1::RunInfo> SqliteStore::EndQueuedRun(const std::string& run_id, v1::RunState state,
                                                     const std::string& message,
                                                     int64_t now_unix_ms) {
  std::lock_guard lock(impl_->mutex);
  SqliteTransaction transaction(impl_->db, "end queued run " + run_id);
  SqliteStatement select(impl_->db, "SELECT info FROM runs WHERE id = ?1 AND state = ?2",
                         "end a queued run");
  std::vector<v1::RunInfo> queued =
      SelectRuns(*impl_, select, "end a queued run", [&](SqliteStatement& s) {
        s.BindText(1, run_id);
        s.BindInt64(2, v1::QUEUED);
      });
  if (queued.empty()) return std::nullopt;
  v1::RunInfo& info = queued.front();
  info.set_state(state);
  info.set_message(message);
  info.set_ended_unix_ms(now_unix_ms);
  UpsertRunLocked(*impl_, info);
  transaction.Commit();
  return info;
}

}  // namespace mbstream
