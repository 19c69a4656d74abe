#include "server/runs/sweep_coordinates.h"

#include <algorithm>

#include "server/model/coordinate_names.h"
#include "shared/common/check.h"
#include "shared/common/did_you_mean.h"

namespace mbstream {

namespace {

struct Vector {
  const char* field;  // initial_q or initial_qd, as a path starts
  std::vector<std::string> names;
  bool used = false;
};

// `path` with its first step's [NAME] replaced by the name's index, when the step is one of
// `vectors` and NAME is not a number; marks the vector used whenever the path indexes it.
std::string Resolve(const std::string& path, std::vector<Vector>& vectors) {
  for (Vector& vector : vectors) {
    const std::string open = std::string(vector.field) + "[";
    if (path.rfind(open, 0) != 0) continue;
    vector.used = true;
    const size_t close = path.find(']', open.size());
    if (close == std::string::npos) return path;  // ApplySpecOverride names the problem
    const std::string inside = path.substr(open.size(), close - open.size());
    if (!inside.empty() &&
        std::all_of(inside.begin(), inside.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      return path;
    }
    const auto at = std::find(vector.names.begin(), vector.names.end(), inside);
    if (at == vector.names.end()) {
      throw InputError(
          "sweep: " + path + ": the model has no coordinate '" + inside + "'" +
          DidYouMean(inside, vector.names) + "; give an index or a name of the model's " +
          vector.field + " coordinates (the columns of a run's " +
          (vector.field == std::string("initial_q") ? "joints.csv" : "velocities.csv") + ")");
    }
    return open + std::to_string(at - vector.names.begin()) + path.substr(close);
  }
  return path;
}

}  // namespace

void ResolveCoordinatePaths(const Model& model, v1::SweepDefinition* definition) {
  std::vector<Vector> vectors = {{"initial_q", PositionNames(model)},
                                 {"initial_qd", VelocityNames(model)}};
  for (v1::SweepDefinition::Axis& axis : *definition->mutable_grid()) {
    axis.set_path(Resolve(axis.path(), vectors));
  }
  for (std::string& path : *definition->mutable_list_paths()) path = Resolve(path, vectors);
  v1::RunSpec* base = definition->mutable_base();
  if (vectors[0].used && base->initial_q_size() == 0) {
    base->mutable_initial_q()->Resize(model.nq(), 0.0);
    NeutralPositions(model, base->mutable_initial_q()->mutable_data());
  }
  if (vectors[1].used && base->initial_qd_size() == 0) {
    base->mutable_initial_qd()->Resize(model.nv(), 0.0);
  }
}

}  // namespace mbstream
