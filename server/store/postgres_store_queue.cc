// PostgresStore: the run queue (claims, leases, expiry), each call one transaction. A claim
// locks the oldest queued row with FOR UPDATE SKIP LOCKED, so replicas claiming at the same
// time take different runs and never wait for each other.
#include "server/store/postgres_store.h"
#include "server/store/postgres_store_impl.h"

namespace mbstream {
namespace {

constexpr int kQueued = v1::QUEUED;
constexpr int kRunning = v1::RUNNING;

std::vector<v1::RunInfo> Infos(const pqxx::result& rows, const std::string& what,
                               const std::string& location) {
  std::vector<v1::RunInfo> runs;
  pqxx::binarystring blob(nullptr, 0);
  for (const pqxx::row& row : rows) {
    ParseFromStore(BlobOf(row[0], blob), runs.emplace_back(), what, location);
  }
  return runs;
}

// Writes `info` and its lease (none when `holder` is null) in `tx`.
void UpdateRun(pqxx::work& tx, const v1::RunInfo& info, const std::string* holder,
               int64_t expires_unix_ms) {
  UpsertRun(tx, info);
  if (holder != nullptr) {
    tx.exec_params("UPDATE runs SET lease_holder = $2, lease_expires_unix_ms = $3 WHERE id = $1",
                   info.id(), *holder, expires_unix_ms);
  } else {
    tx.exec_params("UPDATE runs SET lease_holder = NULL, lease_expires_unix_ms = 0 WHERE id = $1",
                   info.id());
  }
}

}  // namespace

bool HoldsLease(pqxx::transaction_base& tx, const std::string& run_id, const std::string& holder) {
  return !tx.exec_params(
                "SELECT 1 FROM runs WHERE id = $1 AND state = $2 AND lease_holder = $3 "
                "FOR UPDATE",
                run_id, kRunning, holder)
              .empty();
}

std::optional<v1::RunInfo> PostgresStore::ClaimQueuedRun(const RunLease& lease) {
  return impl_->Transact("claim a queued run", [&](pqxx::work& tx) {
    std::vector<v1::RunInfo> oldest =
        Infos(tx.exec_params("SELECT info FROM runs WHERE state = $1 "
                             "ORDER BY created_unix_ms, ord LIMIT 1 FOR UPDATE SKIP LOCKED",
                             kQueued),
              "queued run", impl_->location);
    std::optional<v1::RunInfo> claimed;
    if (oldest.empty()) return claimed;
    claimed = std::move(oldest.front());
    ApplyClaim(*claimed, lease);
    const std::string holder = LeaseHolder(*claimed);
    UpdateRun(tx, *claimed, &holder, lease.expires_unix_ms);
    return claimed;
  });
}

bool PostgresStore::RenewLease(const std::string& run_id, const std::string& holder,
                               int64_t expires_unix_ms) {
  return impl_->Transact("renew the lease of run " + run_id, [&](pqxx::work& tx) {
    return tx.exec_params(
                 "UPDATE runs SET lease_expires_unix_ms = $3 "
                 "WHERE id = $1 AND state = $4 AND lease_holder = $2",
                 run_id, holder, expires_unix_ms, kRunning)
               .affected_rows() == 1;
  });
}

std::vector<v1::RunInfo> PostgresStore::ReapExpiredLeases(int64_t now_unix_ms,
                                                          const std::string& reaper) {
  return impl_->Transact("reap expired run leases", [&](pqxx::work& tx) {
    std::vector<v1::RunInfo> expired =
        Infos(tx.exec_params("SELECT info FROM runs WHERE state = $1 AND "
                             "lease_expires_unix_ms < $2 ORDER BY ord FOR UPDATE SKIP LOCKED",
                             kRunning, now_unix_ms),
              "run with an expired lease", impl_->location);
    for (v1::RunInfo& info : expired) {
      if (ApplyLeaseExpired(info, now_unix_ms, reaper) == v1::INTERRUPTED) {
        ApplyKeptFrames(KeptFramesOf(tx, info.id()), info);
      }
      UpdateRun(tx, info, nullptr, 0);
    }
    return expired;
  });
}

std::vector<v1::RunInfo> PostgresStore::ListRunningRuns() const {
  return impl_->Transact("list running runs", [&](pqxx::work& tx) {
    return Infos(tx.exec_params("SELECT info FROM runs WHERE state = $1 ORDER BY ord", kRunning),
                 "running run", impl_->location);
  });
}

bool PostgresStore::PutRunIfHeld(const v1::RunInfo& info, const std::string& holder) {
  return impl_->Transact("write run " + info.id(), [&](pqxx::work& tx) {
    if (!HoldsLease(tx, info.id(), holder)) return false;
    UpdateRun(tx, info, nullptr, 0);
    return true;
  });
}

std::optional<v1::RunInfo> PostgresStore::EndQueuedRun(const std::string& run_id,
                                                       v1::RunState state,
                                                       const std::string& message,
                                                       int64_t now_unix_ms) {
  return impl_->Transact("end queued run " + run_id, [&](pqxx::work& tx) {
    std::vector<v1::RunInfo> queued =
        Infos(tx.exec_params("SELECT info FROM runs WHERE id = $1 AND state = $2 FOR UPDATE",
                             run_id, kQueued),
              "run " + run_id, impl_->location);
    std::optional<v1::RunInfo> ended;
    if (queued.empty()) return ended;
    ended = std::move(queued.front());
    ended->set_state(state);
    ended->set_message(message);
    ended->set_ended_unix_ms(now_unix_ms);
    UpsertRun(tx, *ended);
    return ended;
  });
}

}  // namespace mbstream
