// Where something is in a scene script: 1-based line and column (bytes).
#pragma once

namespace mbstream::scene_script {

struct SourcePosition {
  int line = 0;
  int column = 0;
};

}  // namespace mbstream::scene_script
