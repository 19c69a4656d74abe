#include "server/sim/loop_plan.h"

#include <algorithm>

#include "server/body/body_cuts.h"
#include "server/integrate/failure_messages.h"
#include "server/kinematics/coordinate_step.h"
#include "server/sim/body_run.h"
#include "server/sim/initial_state.h"
#include "shared/common/check.h"
#include "shared/common/format.h"

namespace mbstream {

namespace {

void CheckSupported(const RunConfig& config, const DriveSet& drives) {
  for (int i = 0; i < drives.size(); ++i) {
    if (drives.velocity_source(i)) {
      throw InputError(
          "a mechanism with closed loops takes prescribed joints by position, not as velocity "
          "sources (yet): drop velocity_source from the drives");
    }
  }
  if (config.target.any() && !config.method_auto && config.method != Method::kBdf &&
      config.method != Method::kIda) {
    throw InputError(std::string("an accuracy target on a mechanism with closed loops chooses "
                                 "the tolerance of bdf (with projection) or ida, not ") +
                     MethodName(config.method) + ": use method auto, bdf or ida");
  }
  if (config.method_auto && !config.target.any()) {
    throw InputError(
        "method auto chooses for an accuracy target: give target_tcp, target_joint or "
        "target_energy, or a method (bdf) and tolerances");
  }
  if (config.formulation == Formulation::kBodyIndex3) {
    // Measured on the four-bar and the slider-crank (tests/server/loops/body_loop_test.cc):
    // IDA's Newton iteration fails in the first step at rtol 1e-7 to 1e-10, by 0.05 s at
    // 1e-6, on the position-level rows of the loops.
    throw InputError(
        "formulation body-index3 does not close kinematic loops: with the cut joints' "
        "position-level constraints IDA's Newton iteration fails from the first step; use "
        "formulation body-index2 (method ida) or body-baumgarte (method bdf) for body "
        "coordinates, or joint");
  }
}

// The loop whose equations are worst violated in phi, for messages.
const LoopClosure& WorstLoop(const std::vector<LoopClosure>& loops, const LoopConstraints& c,
                             const Eigen::VectorXd& phi) {
  Eigen::Index worst = 0;
  phi.cwiseAbs().maxCoeff(&worst);
  return loops[c.rows()[worst].loop];
}

}  // namespace

LoopPlan PlanLoopRun(const Model& model, const std::vector<LoopClosure>& loops,
                     const RunConfig& config, const DriveSet& drives) {
  MBSTREAM_CHECK(!loops.empty());
  CheckSupported(config, drives);
  if (IsBodyFormulation(config.formulation)) CheckBodyFormulationCloses(loops);
  const int n = model.nv(), nq = model.nq();
  const std::vector<int> prescribed = PrescribedJoints(drives);
  const Eigen::VectorXd y0 = InitialJointState(config, drives, model);
  LoopPlan plan;
  plan.q0 = y0.head(nq);
  plan.qd0 = y0.tail(n);
  Data data(model);
  LoopConstraints constraints(model, loops);
  LoopSolver solver(model, constraints, prescribed);
  bool independent = false;
  solver.Analyse(data, plan.q0, &independent);
  const Eigen::VectorXd given = plan.q0;  // the prescribed joints' values among them
  // The same by velocity coordinate, as the solver holds them (given itself without
  // quaternions).
  Eigen::VectorXd held_q = given;
  if (model.has_quaternions()) {
    const std::vector<int> q_of_v = PositionOfVelocity(model);
    held_q = Eigen::VectorXd::Zero(n);
    for (int i = 0; i < n; ++i) held_q(i) = q_of_v[i] >= 0 ? given(q_of_v[i]) : 0.0;
  }
  const int iterations = solver.SolvePositions(data, plan.q0, held_q, kLoopAssemblyTolerance, 50);
  if (iterations < 0) {
    const Eigen::VectorXd& phi = solver.residual();
    const LoopClosure& loop = WorstLoop(loops, constraints, phi);
    if (loop.type == LoopJointType::kMimic) {
      throw InputError(FormatString(
          "%s: joint '%s' follows joint '%s' (<mimic>: %g times its value %+g), but the "
          "pose cannot be made to meet that near the given one (largest residual %.3g m or "
          "rad): a prescribed follower, or couplings that contradict each other; prescribe "
          "the leader, not the follower, check the <mimic> multipliers and offsets, or give "
          "initial_q that meets them",
          loop.where.c_str(), loop.name.c_str(), model.bodies[loop.body_a].joint.name.c_str(),
          loop.multiplier, loop.offset, phi.cwiseAbs().maxCoeff()));
    }
    throw InputError(FormatString(
        "%s: joint '%s': the loop it closes cannot be assembled near the given pose (largest "
        "residual %.3g m or rad after 50 Newton iterations); check the link lengths and joint "
        "poses, or give initial_q nearer an assembled pose",
        loop.where.c_str(), loop.name.c_str(), phi.cwiseAbs().maxCoeff()));
  }
  plan.assembly_iterations = iterations;
  plan.assembly_change = nq > 0 ? (plan.q0 - given).cwiseAbs().maxCoeff() : 0.0;
  plan.rank = solver.Analyse(data, plan.q0, &independent);
  if (!independent) {
    throw InputError(FormatString(
        "%d joint(s) are prescribed, but the loops already fix some of them (the mechanism has "
        "%d degree(s) of freedom): prescribe only independent joints, e.g. the crank",
        static_cast<int>(prescribed.size()), plan.rank.mobility));
  }
  solver.SolvePositions(data, plan.q0, held_q, kLoopAssemblyTolerance, 5);
  const Eigen::VectorXd held_qd = plan.qd0;
  solver.SolveVelocities(data, plan.qd0, held_qd);
  plan.assembly = iterations == 0
                      ? "the given pose closes every loop"
                      : FormatString(
                            "assembled by Newton near the given pose: %d iteration(s), joints "
                            "moved by up to %.3g rad or m",
                            iterations, plan.assembly_change);

  const int free_dofs = plan.rank.mobility - static_cast<int>(prescribed.size());
  const std::string mobility =
      FormatString("%d loop equation(s), %d independent, mobility %d", plan.rank.equations,
                   plan.rank.rank, plan.rank.mobility);
  if (IsBodyFormulation(config.formulation)) {
    plan.choice = ChooseFormulation(config, drives);  // the tree's reason, the method's checks
    plan.choice.reason += FormatString(
        "; the %d cut joint(s) are joints between two bodies like the tree's (%s: the dependent "
        "rows are dropped at the initial pose)",
        static_cast<int>(loops.size()), mobility.c_str());
    return plan;
  }
  if (config.formulation == Formulation::kKinematic && free_dofs > 0) {
    throw InputError(FormatString(
        "formulation kinematic needs every degree of freedom prescribed, but the mechanism "
        "has %d (%s) and %d joint(s) are prescribed; prescribe %d more (e.g. the crank) or use "
        "formulation joint",
        plan.rank.mobility, mobility.c_str(), static_cast<int>(prescribed.size()), free_dofs));
  }
  if (free_dofs == 0 && config.formulation != Formulation::kJoint) {
    plan.choice = {
        Formulation::kKinematic,
        std::string(config.formulation == Formulation::kAuto ? "auto: " : "requested: ") +
            "every degree of freedom is prescribed (" + mobility +
            "), so the loops are solved by Newton at each frame and nothing is "
            "integrated"};
  } else {
    const std::string how =
        config.method == Method::kIda
            ? "the joint-space index-2 stabilised DAE of Gear, Gupta and Leimkuhler with IDA "
              "(positions and velocities constrained, no gains)"
            : FormatString(
                  "the joint-space ODE with the loops as constraints (Baumgarte alpha "
                  "= %g 1/s, beta = %g 1/s^2%s)",
                  config.baumgarte.alpha, config.baumgarte.beta,
                  config.method == Method::kBdf ? ", projected onto the constraints after each step"
                                                : "; projection needs method bdf");
    plan.choice = {
        Formulation::kJoint,
        std::string(config.formulation == Formulation::kAuto ? "auto: " : "requested: ") +
            FormatString("%d degree(s) of freedom move freely (%s): ", free_dofs,
                         mobility.c_str()) +
            how};
  }
  return plan;
}

}  // namespace mbstream
