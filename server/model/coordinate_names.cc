#include "server/model/coordinate_names.h"

namespace mbstream {

namespace {

template <int N, int M>
std::vector<std::string> Names(const Model& model, const char* const (&free)[N],
                               const char* const (&ball)[M]) {
  std::vector<std::string> names;
  for (const Body& body : model.bodies) {
    if (body.free()) {
      for (const char* suffix : free) names.push_back(body.joint.name + suffix);
    } else if (body.ball()) {
      for (const char* suffix : ball) names.push_back(body.joint.name + suffix);
    } else {
      names.push_back(body.joint.name);
    }
  }
  return names;
}

}  // namespace

std::vector<std::string> PositionNames(const Model& model) {
  return Names(model, kFreePositionSuffixes, kBallPositionSuffixes);
}

std::vector<std::string> VelocityNames(const Model& model) {
  return Names(model, kFreeVelocitySuffixes, kBallVelocitySuffixes);
}

}  // namespace mbstream
