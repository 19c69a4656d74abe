#include "server/runs/model_id.h"

#include <openssl/evp.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

#include "shared/common/check.h"

namespace mbstream {

namespace {

class Sha256 {
 public:
  Sha256() : context_(EVP_MD_CTX_new(), EVP_MD_CTX_free) {
    MBSTREAM_CHECK(context_ != nullptr);
    MBSTREAM_CHECK(EVP_DigestInit_ex(context_.get(), EVP_sha256(), nullptr) == 1);
  }
  // Adds the field's length (8 bytes, little endian) and then its bytes.
  void AddField(const std::string& bytes) {
    uint64_t size = bytes.size();
    unsigned char prefix[8];
    for (int i = 0; i < 8; ++i) prefix[i] = static_cast<unsigned char>(size >> (8 * i));
    MBSTREAM_CHECK(EVP_DigestUpdate(context_.get(), prefix, sizeof(prefix)) == 1);
    MBSTREAM_CHECK(EVP_DigestUpdate(context_.get(), bytes.data(), bytes.size()) == 1);
  }
  std::string HexDigest() {
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int length = 0;
    MBSTREAM_CHECK(EVP_DigestFinal_ex(context_.get(), digest, &length) == 1);
    static const char kHex[] = "0123456789abcdef";
    std::string hex;
    for (unsigned int i = 0; i < length; ++i) {
      hex += kHex[digest[i] >> 4];
      hex += kHex[digest[i] & 15];
    }
    return hex;
  }

 private:
  std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> context_;
};

}  // namespace

std::string ModelContentId(const v1::ModelBundle& bundle) {
  Sha256 hash;
  hash.AddField("mbstream model bundle v1");
  hash.AddField(bundle.urdf());
  hash.AddField(bundle.scene_script());
  std::vector<const v1::Asset*> assets;
  for (const v1::Asset& asset : bundle.assets()) assets.push_back(&asset);
  std::sort(assets.begin(), assets.end(),
            [](const v1::Asset* a, const v1::Asset* b) { return a->name() < b->name(); });
  for (const v1::Asset* asset : assets) {
    hash.AddField(asset->name());
    hash.AddField(asset->data());
  }
  // Appended only when set, so that the ids of bundles without these options stay as they
  // were.
  if (bundle.repair()) hash.AddField("repair");
  if (bundle.couple_mimic()) hash.AddField("couple_mimic");
  if (bundle.floating_base()) hash.AddField("floating_base");
  return "m-" + hash.HexDigest().substr(0, 24);
}

}  // namespace mbstream
