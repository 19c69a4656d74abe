// Runs urdfdom's parser and turns what it logs into mbstream messages.
#pragma once

#include <memory>
#include <string>

#include <urdf_model/model.h>

#include "server/parse/urdf_diagnostics.h"

namespace mbstream {

// Parses URDF XML `text` with urdf::parseURDF. urdfdom reports problems only through
// console_bridge's log; they are captured (the log is silenced meanwhile). Throws
// InputError quoting urdfdom's messages when it fails or logs an error (for some errors,
// such as a bad <inertial>, it logs and carries on with zeros). Its warnings are kept.
std::shared_ptr<urdf::ModelInterface> ParseWithUrdfdom(const std::string& text,
                                                       const UrdfDiagnostics& diagnostics);

}  // namespace mbstream
