#include "shared/net/tls_files.h"

#include <fstream>
#include <sstream>

namespace mbstream::net {

std::string ReadSecurityFile(const std::string& path, const std::string& flag) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SecurityConfigError(flag + " " + path + ": cannot read the file; check the path");
  std::ostringstream text;
  text << in.rdbuf();
  if (text.str().empty()) throw SecurityConfigError(flag + " " + path + ": the file is empty");
  return text.str();
}

bool IsLocalAddress(const std::string& address) {
  return address.rfind("unix:", 0) == 0 || address.rfind("127.", 0) == 0 ||
         address.rfind("localhost:", 0) == 0 || address.rfind("[::1]", 0) == 0 ||
         address.rfind("ipv4:127.", 0) == 0;
}

}  // namespace mbstream::net
