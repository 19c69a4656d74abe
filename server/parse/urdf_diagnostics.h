// Messages that point into a URDF file, and the warnings collected while importing it.
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mbstream {

// "FILE:LINE: KIND 'NAME'", or "FILE: KIND 'NAME'" when `line` is 0 (unknown). Every
// importer message starts with it and goes on with ": what is wrong; what to do".
std::string Where(const std::string& source, int line, std::string_view kind,
                  std::string_view name);

// Knows the file name and the line of each link and joint; collects warnings.
class UrdfDiagnostics {
 public:
  UrdfDiagnostics(std::string source, std::map<std::string, int> link_lines,
                  std::map<std::string, int> joint_lines, std::vector<std::string>* warnings,
                  bool repair = false)
      : source_(std::move(source)),
        link_lines_(std::move(link_lines)),
        joint_lines_(std::move(joint_lines)),
        warnings_(warnings),
        repair_(repair) {}

  const std::string& source() const { return source_; }
  std::string Link(const std::string& name) const;       // "FILE:LINE: link 'NAME'"
  std::string Joint(const std::string& name) const;      // "FILE:LINE: joint 'NAME'"
  std::string JointLine(const std::string& name) const;  // "FILE:LINE" (or "FILE")
  void Warn(std::string message) const { warnings_->push_back(std::move(message)); }
  // Whether defects that have a repair are repaired (with a warning) rather than errors.
  bool repair() const { return repair_; }

 private:
  std::string source_;
  std::map<std::string, int> link_lines_;
  std::map<std::string, int> joint_lines_;
  std::vector<std::string>* warnings_;
  bool repair_ = false;
};

// What an error about a repairable defect says last.
inline constexpr char kRepairHint[] =
    "; or import with --repair (mbstream submit/simulate) to fix it with a warning";

// `value` with up to 15 significant digits ("0.5", "1e-07").
std::string FormatNumber(double value);

}  // namespace mbstream
