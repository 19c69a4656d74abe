// Store: models and their bundles (assets in their own rows).
#include <utility>

#include "server/store/sqlite_store.h"
#include "server/store/sqlite_transaction.h"
#include "server/store/store_impl.h"

namespace mbstream {

bool SqliteStore::PutModel(const v1::ModelInfo& info, const v1::ModelBundle& bundle) {
  const EncodedModel model = EncodeModelForStore(info, bundle);
  const std::string what = "model " + info.id();

  std::lock_guard lock(impl_->mutex);
  SqliteTransaction transaction(impl_->db, "store " + what);
  {
    SqliteStatement& insert = impl_->insert_model;
    ResetOnExit reset(insert);
    insert.BindText(1, info.id());
    insert.BindInt64(2, model.created_unix_ms);
    insert.BindBlob(3, model.info);
    insert.BindBlob(4, model.bundle);
    insert.Run();
  }
  if (impl_->db.Changes() == 0) return false;  // the first stored copy wins; rolls back
  for (int i = 0; i < bundle.assets_size(); ++i) {
    SqliteStatement& insert = impl_->insert_asset;
    ResetOnExit reset(insert);
    insert.BindText(1, info.id());
    insert.BindInt64(2, i);
    insert.BindText(3, bundle.assets(i).name());
    insert.BindBlob(4, bundle.assets(i).data());
    insert.Run();
  }
  transaction.Commit();
  return true;
}

std::vector<v1::ModelInfo> SqliteStore::ListModels() const {
  std::vector<v1::ModelInfo> models;
  std::lock_guard lock(impl_->mutex);
  SqliteStatement& select = impl_->select_model_infos;
  ResetOnExit reset(select);
  while (select.Step()) {
    ParseFromStore(select.ColumnBlob(0), models.emplace_back(), "model info", impl_->db.path());
  }
  return models;
}

std::optional<v1::ModelBundle> SqliteStore::GetModelBundle(const std::string& model_id,
                                                           bool asset_data) const {
  v1::ModelBundle bundle;
  std::lock_guard lock(impl_->mutex);
  {
    SqliteStatement& select = impl_->select_model_bundle;
    ResetOnExit reset(select);
    select.BindText(1, model_id);
    if (!select.Step()) return std::nullopt;
    ParseFromStore(select.ColumnBlob(0), bundle, "bundle of model " + model_id, impl_->db.path());
  }
  SqliteStatement& select =
      asset_data ? impl_->select_model_assets : impl_->select_model_asset_names;
  ResetOnExit reset(select);
  select.BindText(1, model_id);
  while (select.Step()) {
    v1::Asset* asset = bundle.add_assets();
    asset->set_name(std::string(select.ColumnText(0)));
    if (asset_data) asset->set_data(std::string(select.ColumnBlob(1)));
  }
  return bundle;
}

std::map<std::string, int64_t> SqliteStore::ModelBytes() const {
  std::map<std::string, int64_t> sizes;
  std::lock_guard lock(impl_->mutex);
  SqliteStatement& select = impl_->select_model_bytes;
  ResetOnExit reset(select);
  while (select.Step()) sizes[std::string(select.ColumnText(0))] = select.ColumnInt64(1);
  return sizes;
}

}  // namespace mbstream
