#include "server/wire/model_info.h"

#include <cmath>

#include "server/model/coordinate_names.h"

namespace mbstream {

namespace {

double FiniteOrZero(double value) { return std::isfinite(value) ? value : 0.0; }

void AddFormulation(const char* name, int equations, int nnz, v1::ModelInfo* info) {
  v1::FormulationSize* size = info->add_formulations();
  size->set_formulation(name);
  size->set_equations(equations);
  size->set_jacobian_nnz(nnz);
}

}  // namespace

void DescribeModel(const Model& model, const std::vector<std::string>& warnings,
                   v1::ModelInfo* info) {
  info->set_dofs(model.num_dofs());
  info->set_positions(model.nq());
  info->clear_position_names();
  for (const std::string& name : PositionNames(model)) info->add_position_names(name);
  info->clear_velocity_names();
  for (const std::string& name : VelocityNames(model)) info->add_velocity_names(name);
  info->clear_joints();
  for (const Body& body : model.bodies) {
    v1::JointInfo* joint = info->add_joints();
    joint->set_name(body.joint.name);
    joint->set_type(JointTypeName(body.joint.type));
    const JointLimits& limits = body.joint.limits;
    const bool limited =
        body.nv() == 1 && std::isfinite(limits.lower) && std::isfinite(limits.upper);
    joint->set_lower(limited ? limits.lower : 0.0);
    joint->set_upper(limited ? limits.upper : 0.0);
    joint->set_velocity_limit(FiniteOrZero(limits.velocity));
    joint->set_effort_limit(FiniteOrZero(limits.effort));
  }
  info->set_tcp_frame(model.tcp_frame >= 0 ? model.frames[model.tcp_frame].name : "");
  info->set_links(static_cast<int>(model.frames.size()));  // every link and named point
  info->set_total_mass_kg(FiniteOrZero(model.TotalMass()));
  info->clear_formulations();
  const int n = model.num_dofs();
  const int nq = model.nq();
  AddFormulation("kinematic", 0, 0, info);
  // The joint-space ODE's Newton matrix with no prescribed joint: the identity block of
  // q' = qd (n) and the dense accelerations' rows (n x 2n), as its runs report (with free
  // bodies nq + n states).
  AddFormulation("joint", nq + n, n + 2 * n * n, info);
  info->clear_warnings();
  for (const std::string& warning : warnings) info->add_warnings(warning);
}

std::vector<std::string> JointNames(const Model& model) { return VelocityNames(model); }

}  // namespace mbstream
