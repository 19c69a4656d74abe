#include "server/parse/urdfdom_parse.h"

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include <exception>
#include <mutex>
#include <regex>
#include <vector>

#include "shared/common/check.h"

namespace mbstream {

namespace {

// Collects console_bridge messages while urdfdom parses.
class CapturingHandler : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char* /*filename*/,
           int /*line*/) override {
    (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR ? errors : warnings).push_back(text);
  }
  std::vector<std::string> errors;
  std::vector<std::string> warnings;
};

// console_bridge's handler is process-wide: one parse at a time.
std::mutex& ParseMutex() {
  static std::mutex mutex;
  return mutex;
}

// Where urdfdom's messages point: "FILE:LINE: joint 'NAME'" for the first joint they
// name, else "FILE:LINE: link 'NAME'" for the first link, else just "FILE". urdfdom writes
// "joint [NAME]", "Joint [NAME]", "joint 'NAME'", and the same for links.
std::string WhereUrdfdomPoints(const std::vector<std::string>& messages,
                               const UrdfDiagnostics& diagnostics) {
  static const std::regex kJoint(R"(\b[Jj]oint (?:\[([^\]]+)\]|'([^']+)'))");
  static const std::regex kLink(R"(\b[Ll]ink (?:\[([^\]]+)\]|'([^']+)'))");
  for (const std::regex* pattern : {&kJoint, &kLink}) {
    for (const std::string& message : messages) {
      std::smatch match;
      if (!std::regex_search(message, match, *pattern)) continue;
      const std::string name = match[1].matched ? match[1].str() : match[2].str();
      return pattern == &kJoint ? diagnostics.Joint(name) : diagnostics.Link(name);
    }
  }
  return diagnostics.source();
}

std::string Joined(const std::vector<std::string>& messages) {
  std::string all;
  for (const std::string& message : messages) {
    if (!all.empty()) all += "; ";
    all += message;
  }
  return all;
}

}  // namespace

std::shared_ptr<urdf::ModelInterface> ParseWithUrdfdom(const std::string& text,
                                                       const UrdfDiagnostics& diagnostics) {
  // Never destroyed: console_bridge keeps a pointer to the previous handler.
  static CapturingHandler* const handler = new CapturingHandler;
  std::shared_ptr<urdf::ModelInterface> model;
  std::vector<std::string> errors;
  std::vector<std::string> warnings;
  {
    const std::lock_guard<std::mutex> lock(ParseMutex());
    handler->errors.clear();
    handler->warnings.clear();
    console_bridge::OutputHandler* const previous_handler = console_bridge::getOutputHandler();
    const console_bridge::LogLevel previous_level = console_bridge::getLogLevel();
    console_bridge::useOutputHandler(handler);
    console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_WARN);
    try {
      model = urdf::parseURDF(text);
    } catch (const std::exception& e) {
      handler->errors.push_back(e.what());
    }
    console_bridge::setLogLevel(previous_level);
    console_bridge::useOutputHandler(previous_handler);
    errors.swap(handler->errors);
    warnings.swap(handler->warnings);
  }

  for (const std::string& warning : warnings) {
    diagnostics.Warn(diagnostics.source() + ": urdfdom: " + warning);
  }
  if (model == nullptr || !errors.empty()) {
    const std::string reason =
        errors.empty() ? std::string("it gave no reason") : "it said: " + Joined(errors);
    throw InputError(WhereUrdfdomPoints(errors, diagnostics) + ": urdfdom cannot parse the URDF (" +
                     reason +
                     "); fix the element as the URDF specification describes "
                     "(https://wiki.ros.org/urdf/XML)");
  }
  MBSTREAM_CHECK(model->getRoot() != nullptr);
  return model;
}

}  // namespace mbstream
