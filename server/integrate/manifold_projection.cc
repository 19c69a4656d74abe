#include "server/integrate/manifold_projection.h"

#include "server/integrate/ode_system.h"

namespace mbstream {

ManifoldProjection* ProjectionOf(OdeSystem& system) {
  auto* projection = dynamic_cast<ManifoldProjection*>(&system);
  return projection != nullptr && projection->Projects() ? projection : nullptr;
}

ManifoldProjection* EveryStepProjectionOf(OdeSystem& system) {
  ManifoldProjection* projection = ProjectionOf(system);
  return projection != nullptr && projection->ProjectsEveryMethod() ? projection : nullptr;
}

}  // namespace mbstream
