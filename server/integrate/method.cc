#include "server/integrate/method.h"

#include "shared/common/name_table.h"

namespace mbstream {

namespace {

constexpr NameTable<Method, 7> kMethods{{
    {Method::kBdf, "bdf"},
    {Method::kAdams, "adams"},
    {Method::kErk, "erk"},
    {Method::kDirk, "dirk"},
    {Method::kIda, "ida"},
    {Method::kRk4, "rk4"},
    {Method::kEuler, "euler"},
}};

}  // namespace

const char* MethodName(Method method) { return NameOf(kMethods, method); }
bool ParseMethod(const std::string& name, Method* method) {
  return ParseName(kMethods, name, method);
}

}  // namespace mbstream
