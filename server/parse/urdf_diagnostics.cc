#include "server/parse/urdf_diagnostics.h"

#include <cstdio>

namespace mbstream {

namespace {

int LineOf(const std::map<std::string, int>& lines, const std::string& name) {
  const auto it = lines.find(name);
  return it == lines.end() ? 0 : it->second;
}

}  // namespace

std::string Where(const std::string& source, int line, std::string_view kind,
                  std::string_view name) {
  std::string where = source;
  if (line > 0) where += ":" + std::to_string(line);
  where += ": ";
  where += kind;
  where += " '";
  where += name;
  where += "'";
  return where;
}

std::string UrdfDiagnostics::Link(const std::string& name) const {
  return Where(source_, LineOf(link_lines_, name), "link", name);
}

std::string UrdfDiagnostics::Joint(const std::string& name) const {
  return Where(source_, LineOf(joint_lines_, name), "joint", name);
}

std::string UrdfDiagnostics::JointLine(const std::string& name) const {
  const int line = LineOf(joint_lines_, name);
  return line > 0 ? source_ + ":" + std::to_string(line) : source_;
}

std::string FormatNumber(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.15g", value);
  return buffer;
}

}  // namespace mbstream
