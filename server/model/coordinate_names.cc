#include "server/model/coordinate_names.h"

namespace mbstream {

namespace {

template <int N>
std::vector<std::string> Names(const Model& model, const char* const (&suffixes)[N]) {
  std::vector<std::string> names;
  for (const Body& body : model.bodies) {
    if (!body.free()) {
      names.push_back(body.joint.name);
      continue;
    }
    for (const char* suffix : suffixes) names.push_back(body.joint.name + suffix);
  }
  return names;
}

}  // namespace

std::vector<std::string> PositionNames(const Model& model) {
  return Names(model, kFreePositionSuffixes);
}

std::vector<std::string> VelocityNames(const Model& model) {
  return Names(model, kFreeVelocitySuffixes);
}

}  // namespace mbstream
