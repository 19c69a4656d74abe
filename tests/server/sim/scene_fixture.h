// Loads the shipped IRB 1600 model and its reference scenes for the simulation tests.
#pragma once

#include <string>

#include "server/parse/urdf_import.h"
#include "server/sim/run_config.h"
#include "server/spec/run_spec_json.h"

namespace mbstream::testing {

inline const Model& Irb1600() {
  static const Model model = ImportUrdfFile("models/irb1600/irb1600.urdf").model;
  return model;
}

// models/irb1600/<name>.json as the core's RunConfig.
inline RunConfig Scene(const std::string& name) {
  const std::string path = "models/irb1600/" + name + ".json";
  std::vector<std::string> joints;
  for (const Body& body : Irb1600().bodies) joints.push_back(body.joint.name);
  return ToRunConfig(LoadRunSpecFile(path), joints, path);
}

}  // namespace mbstream::testing
