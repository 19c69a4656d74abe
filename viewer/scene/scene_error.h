// A scene that cannot be built (an unreadable STL file, no display) or rendered.
#pragma once

#include <stdexcept>
#include <string>

namespace mbstream::viewer {

class SceneError : public std::runtime_error {
 public:
  explicit SceneError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace mbstream::viewer
