#include "server/store/store_location.h"

#include <fstream>
#include <string_view>

#include "server/store/postgres_store.h"
#include "server/store/sqlite_store.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

constexpr std::string_view kSqlitePrefix = "sqlite:";
constexpr std::string_view kPostgresPrefixes[] = {"postgresql://", "postgres://"};
constexpr const char* kForms =
    "--store takes sqlite:DIRECTORY or postgresql://user@host:port/database";

bool StartsWith(std::string_view text, std::string_view prefix) {
  return text.substr(0, prefix.size()) == prefix;
}

}  // namespace

StoreLocation ParseStoreLocation(const std::string& text) {
  for (const char c : text) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      throw InputError(std::string(kForms) + "; the value given holds a control character");
    }
  }
  StoreLocation location;
  if (StartsWith(text, kSqlitePrefix)) {
    location.target = text.substr(kSqlitePrefix.size());
    if (location.target.empty()) {
      throw InputError(std::string(kForms) + "; sqlite: needs a directory (sqlite:mbstream-data)");
    }
    return location;
  }
  for (const std::string_view prefix : kPostgresPrefixes) {
    if (!StartsWith(text, prefix)) continue;
    const std::string_view rest = std::string_view(text).substr(prefix.size());
    const std::string_view authority = rest.substr(0, rest.find_first_of("/?"));
    const std::size_t at = authority.rfind('@');
    if (at != std::string_view::npos && authority.substr(0, at).find(':') != std::string::npos) {
      throw InputError(
          "the --store URI holds a password, which anyone could read in the process "
          "list; remove it and put it in a file given with --store-password-file, "
          "or in PGPASSFILE");
    }
    location.kind = StoreLocation::Kind::kPostgresql;
    location.target = text;
    return location;
  }
  throw InputError(std::string(kForms) + "; got \"" + text + "\"");
}

std::string ReadStorePasswordFile(const std::string& path) {
  std::ifstream in(path);
  std::string password;
  if (!in || !std::getline(in, password)) {
    throw InputError("cannot read the store password file " + path +
                     "; give --store-password-file a readable file holding the password");
  }
  if (!password.empty() && password.back() == '\r') password.pop_back();
  if (password.empty()) {
    throw InputError("the store password file " + path +
                     " is empty; put the password on its first line");
  }
  return password;
}

std::unique_ptr<Store> OpenStore(const StoreLocation& location) {
  if (location.kind == StoreLocation::Kind::kPostgresql) {
    return PostgresStore::Open(location.target, location.password);
  }
  return SqliteStore::Open(location.target);
}

}  // namespace mbstream
