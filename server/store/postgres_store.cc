// PostgresStore::Open, the prepared statements, models and runs.
#include "server/store/postgres_store.h"

#include <cctype>
#include <utility>

#include "server/store/postgres_schema.h"
#include "server/store/postgres_store_impl.h"
#include "server/store/sweep_sql.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

// Statement name and text, prepared once per connection (libpqxx prepares them again after
// it reconnects).
constexpr std::pair<const char*, const char*> kStatements[] = {
    {"insert_model",
     "INSERT INTO models (id, created_unix_ms, info, bundle) VALUES ($1, $2, $3, $4) "
     "ON CONFLICT (id) DO NOTHING"},
    {"insert_asset",
     "INSERT INTO model_assets (model_id, position, name, data) VALUES ($1, $2, $3, $4)"},
    {"select_model_infos", "SELECT info FROM models ORDER BY created_unix_ms, ord"},
    {"select_model_bundle", "SELECT bundle FROM models WHERE id = $1"},
    {"select_model_assets",
     "SELECT name, data FROM model_assets WHERE model_id = $1 ORDER BY position"},
    {"select_model_asset_names",
     "SELECT name FROM model_assets WHERE model_id = $1 ORDER BY position"},
    {"select_model_bytes",
     "SELECT m.id, octet_length(m.bundle) + COALESCE((SELECT sum(octet_length(a.data)) "
     "FROM model_assets a WHERE a.model_id = m.id), 0) FROM models m"},
    {"upsert_run",
     "INSERT INTO runs (id, model_id, state, created_unix_ms, info, sweep_id, sweep_point) "
     "VALUES ($1, $2, $3, $4, $5, NULLIF($6, ''), $7) "
     "ON CONFLICT (id) DO UPDATE SET model_id = excluded.model_id, state = excluded.state, "
     "created_unix_ms = excluded.created_unix_ms, info = excluded.info, "
     "sweep_id = excluded.sweep_id, sweep_point = excluded.sweep_point"},
    {"insert_new_run",
     "INSERT INTO runs (id, model_id, state, created_unix_ms, info, sweep_id, sweep_point) "
     "VALUES ($1, $2, $3, $4, $5, NULLIF($6, ''), $7) ON CONFLICT (id) DO NOTHING"},
    {"select_run", "SELECT info, keep, sweep_cancelled FROM runs WHERE id = $1"},
    {"select_runs", "SELECT info, keep, sweep_cancelled FROM runs ORDER BY created_unix_ms, ord"},
    {"select_unfinished_runs", kSelectUnfinishedRunsForUpdateSql},
    {"delete_frame_chunks", "DELETE FROM frame_chunks WHERE run_id = $1"},
    {"delete_frame_chunks_after", "DELETE FROM frame_chunks WHERE run_id = $1 AND chunk > $2"},
    {"upsert_frame_chunk",
     "INSERT INTO frame_chunks (run_id, chunk, first_seq, frame_count, data) "
     "VALUES ($1, $2, $3, $4, $5) ON CONFLICT (run_id, chunk) DO UPDATE SET "
     "first_seq = excluded.first_seq, frame_count = excluded.frame_count, data = excluded.data"},
    {"select_frame_chunk",
     "SELECT chunk, data FROM frame_chunks WHERE run_id = $1 AND chunk >= $2 "
     "ORDER BY chunk LIMIT 1"},
    {"select_frame_chunk_holding",
     "SELECT chunk FROM frame_chunks WHERE run_id = $1 AND first_seq <= $2 "
     "AND first_seq + frame_count > $2 ORDER BY chunk LIMIT 1"},
    {"select_probes", "SELECT report FROM probes WHERE run_id = $1 ORDER BY seq, probe"},
    {"insert_probe_set", "INSERT INTO probe_sets (id, run_id, info) VALUES ($1, $2, $3)"},
    {"select_probe_sets",
     "SELECT s.info, (SELECT count(*) FROM probe_set_reports r WHERE r.set_id = s.id) "
     "FROM probe_sets s WHERE s.run_id = $1 ORDER BY s.ord"},
    {"select_probe_set",
     "SELECT s.info, (SELECT count(*) FROM probe_set_reports r WHERE r.set_id = s.id) "
     "FROM probe_sets s WHERE s.id = $1"},
    {"select_probe_set_reports",
     "SELECT report FROM probe_set_reports WHERE set_id = $1 ORDER BY seq, probe"},
};

// `uri` with `password` added as a query parameter, percent-encoded.
std::string WithPassword(const std::string& uri, const std::string& password) {
  if (password.empty()) return uri;
  std::string encoded;
  constexpr char kHex[] = "0123456789ABCDEF";
  for (const unsigned char c : password) {
    if (std::isalnum(c) != 0 || c == '-' || c == '_' || c == '.' || c == '~') {
      encoded += static_cast<char>(c);
    } else {
      encoded += '%';
      encoded += kHex[c >> 4];
      encoded += kHex[c & 0xf];
    }
  }
  return uri + (uri.find('?') == std::string::npos ? "?" : "&") + "password=" + encoded;
}

}  // namespace

PostgresStore::Impl::Impl(std::string location_in, std::unique_ptr<pqxx::connection> connection)
    : location(std::move(location_in)), db(std::move(connection)) {
  for (const auto& [name, sql] : kStatements) db->prepare(name, sql);
}

std::unique_ptr<PostgresStore> PostgresStore::Open(const std::string& uri,
                                                   const std::string& password) {
  try {
    auto connection = std::make_unique<pqxx::connection>(WithPassword(uri, password));
    EnsurePostgresSchema(*connection, uri);
    return std::unique_ptr<PostgresStore>(
        new PostgresStore(std::make_unique<Impl>(uri, std::move(connection))));
  } catch (const pqxx::broken_connection& error) {
    throw InputError("cannot connect to the store " + uri + ": " + Trimmed(error.what()) +
                     "; check that PostgreSQL is running there, the database exists and the "
                     "user may log in (password from --store-password-file or PGPASSFILE)");
  } catch (const pqxx::pqxx_exception& error) {
    throw InputError("cannot use the store " + uri + ": " + Trimmed(error.base().what()) +
                     "; give --store a database the user may create tables in");
  }
}

PostgresStore::PostgresStore(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

PostgresStore::~PostgresStore() = default;

const std::string& PostgresStore::path() const { return impl_->location; }

void PostgresStore::ReleaseMemory() {}  // the database server manages its own cache

bool PostgresStore::PutModel(const v1::ModelInfo& info, const v1::ModelBundle& bundle) {
  const EncodedModel model = EncodeModelForStore(info, bundle);
  const std::string what = "model " + info.id();
  return impl_->Transact("store " + what, [&](pqxx::work& tx) {
    const pqxx::result inserted = tx.exec_prepared("insert_model", info.id(), model.created_unix_ms,
                                                   BlobParam(model.info), BlobParam(model.bundle));
    if (inserted.affected_rows() == 0) return false;  // the first stored copy wins
    for (int i = 0; i < bundle.assets_size(); ++i) {
      tx.exec_prepared("insert_asset", info.id(), i, bundle.assets(i).name(),
                       BlobParam(bundle.assets(i).data()));
    }
    return true;
  });
}

std::vector<v1::ModelInfo> PostgresStore::ListModels() const {
  return impl_->Transact("list models", [&](pqxx::work& tx) {
    std::vector<v1::ModelInfo> models;
    pqxx::binarystring blob(nullptr, 0);
    for (const pqxx::row& row : tx.exec_prepared("select_model_infos")) {
      ParseFromStore(BlobOf(row[0], blob), models.emplace_back(), "model info", impl_->location);
    }
    return models;
  });
}

std::optional<v1::ModelBundle> PostgresStore::GetModelBundle(const std::string& model_id,
                                                             bool asset_data) const {
  return impl_->Transact("read model bundle", [&](pqxx::work& tx) {
    std::optional<v1::ModelBundle> bundle;
    const pqxx::result found = tx.exec_prepared("select_model_bundle", model_id);
    if (found.empty()) return bundle;
    pqxx::binarystring blob(nullptr, 0);
    ParseFromStore(BlobOf(found[0][0], blob), bundle.emplace(), "bundle of model " + model_id,
                   impl_->location);
    for (const pqxx::row& row : tx.exec_prepared(
             asset_data ? "select_model_assets" : "select_model_asset_names", model_id)) {
      v1::Asset* asset = bundle->add_assets();
      asset->set_name(row[0].as<std::string>());
      if (asset_data) asset->set_data(std::string(BlobOf(row[1], blob)));
    }
    return bundle;
  });
}

std::map<std::string, int64_t> PostgresStore::ModelBytes() const {
  return impl_->Transact("read model sizes", [&](pqxx::work& tx) {
    std::map<std::string, int64_t> sizes;
    for (const pqxx::row& row : tx.exec_prepared("select_model_bytes")) {
      sizes[row[0].as<std::string>()] = row[1].as<int64_t>();
    }
    return sizes;
  });
}

namespace {

// Runs prepared `statement` (upsert_run or insert_new_run: the same seven parameters) for `info`.
pqxx::result WriteRun(pqxx::transaction_base& tx, const char* statement, const v1::RunInfo& info) {
  const std::string bytes = SerializeForStore(info, "run " + info.id());
  return tx.exec_prepared(statement, info.id(), info.model_id(), static_cast<int>(info.state()),
                          info.created_unix_ms(), BlobParam(bytes), info.sweep_id(),
                          info.sweep_point());
}

}  // namespace

void ReadRunRow(const pqxx::row& row, pqxx::binarystring& blob, v1::RunInfo& info,
                const std::string& location) {
  ParseFromStore(BlobOf(row[0], blob), info, "run info", location);
  info.set_keep(row[1].as<bool>());
  if (row[2].as<bool>()) info.set_sweep_cancelled(true);
}

void UpsertRun(pqxx::transaction_base& tx, const v1::RunInfo& info) {
  WriteRun(tx, "upsert_run", info);
}

bool InsertNewRun(pqxx::transaction_base& tx, const v1::RunInfo& info) {
  return WriteRun(tx, "insert_new_run", info).affected_rows() > 0;
}

void PostgresStore::PutRun(const v1::RunInfo& info) {
  impl_->Transact("write run " + info.id(), [&](pqxx::work& tx) { UpsertRun(tx, info); });
}

namespace {
struct RunIdTaken {};  // leaves Transact without committing: the transaction is aborted
}  // namespace

bool PostgresStore::AddRuns(const std::vector<v1::RunInfo>& infos) {
  try {
    impl_->Transact("write " + std::to_string(infos.size()) + " runs", [&](pqxx::work& tx) {
      for (const v1::RunInfo& info : infos) {
        if (!InsertNewRun(tx, info)) throw RunIdTaken{};
      }
    });
  } catch (const RunIdTaken&) {
    return false;
  }
  return true;
}

std::optional<v1::RunInfo> PostgresStore::GetRun(const std::string& run_id) const {
  return impl_->Transact("read run", [&](pqxx::work& tx) {
    std::optional<v1::RunInfo> info;
    const pqxx::result found = tx.exec_prepared("select_run", run_id);
    if (found.empty()) return info;
    pqxx::binarystring blob(nullptr, 0);
    ReadRunRow(found[0], blob, info.emplace(), impl_->location);
    return info;
  });
}

std::vector<v1::RunInfo> PostgresStore::ListRuns() const {
  return impl_->Transact("list runs", [&](pqxx::work& tx) {
    std::vector<v1::RunInfo> runs;
    pqxx::binarystring blob(nullptr, 0);
    for (const pqxx::row& row : tx.exec_prepared("select_runs")) {
      ReadRunRow(row, blob, runs.emplace_back(), impl_->location);
    }
    return runs;
  });
}

int PostgresStore::MarkUnfinishedRunsInterrupted(const std::string& message) {
  const int64_t now_ms = UnixNowMs();
  return impl_->Transact("mark unfinished runs interrupted", [&](pqxx::work& tx) {
    std::vector<v1::RunInfo> unfinished;
    pqxx::binarystring blob(nullptr, 0);
    for (const pqxx::row& row :
         tx.exec_prepared("select_unfinished_runs", static_cast<int>(v1::QUEUED),
                          static_cast<int>(v1::RUNNING))) {
      ParseFromStore(BlobOf(row[0], blob), unfinished.emplace_back(), "run info", impl_->location);
    }
    for (v1::RunInfo& info : unfinished) {
      MarkInterrupted(info, message, now_ms);
      ApplyKeptFrames(KeptFramesOf(tx, info.id()), info);
      UpsertRun(tx, info);
    }
    return static_cast<int>(unfinished.size());
  });
}

}  // namespace mbstream
