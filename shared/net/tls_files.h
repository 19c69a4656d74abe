// TLS material named on command lines, and reading it.
#pragma once

#include <stdexcept>
#include <string>

namespace mbstream::net {

// Thrown for unreadable or missing security files; the message names the file and flag.
class SecurityConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Reads a PEM (or token) file; throws SecurityConfigError naming `flag` and the path.
std::string ReadSecurityFile(const std::string& path, const std::string& flag);

// True for addresses that never leave this machine: unix:..., 127.x.x.x, localhost, [::1].
bool IsLocalAddress(const std::string& address);

}  // namespace mbstream::net
