#include "server/sim/initial_bodies.h"

#include "shared/common/check.h"

namespace mbstream {

namespace {

template <int N>
void Write(const Eigen::Matrix<double, N, 1>& values, double* to) {
  for (int k = 0; k < N; ++k) to[k] = values[k];
}

}  // namespace

int FindFreeBody(const Model& model, const std::string& name) {
  for (const int i : model.free_bodies) {
    if (model.bodies[i].joint.name == name) return i;
  }
  return -1;
}

void ApplyInitialBodies(const Model& model, const std::vector<InitialBodyState>& bodies, double* q,
                        double* qd) {
  for (const InitialBodyState& state : bodies) {
    const int i = FindFreeBody(model, state.name);
    MBSTREAM_CHECK_MSG(i >= 0, "initial_bodies name a free body: ValidateRun first");
    const Body& body = model.bodies[i];
    double* qi = q + body.q_index;
    double* vi = qd + body.v_index;
    if (state.position) Write(*state.position, qi);
    if (state.quaternion) Write(*state.quaternion, qi + 3);
    if (state.linear_velocity) Write(*state.linear_velocity, vi);
    if (state.angular_velocity) Write(*state.angular_velocity, vi + 3);
  }
}

}  // namespace mbstream
