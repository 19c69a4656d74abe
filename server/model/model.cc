#include "server/model/model.h"

namespace mbstream {

int Model::FindFrame(const std::string& frame_name) const {
  for (size_t i = 0; i < frames.size(); ++i) {
    if (frames[i].name == frame_name) return static_cast<int>(i);
  }
  return -1;
}

int Model::FindBody(const std::string& body_name) const {
  for (size_t i = 0; i < bodies.size(); ++i) {
    if (bodies[i].name == body_name) return static_cast<int>(i);
  }
  return -1;
}

double Model::TotalMass() const {
  double m = 0.0;
  for (const Body& b : bodies) m += b.inertia.mass;
  return m;
}

}  // namespace mbstream
