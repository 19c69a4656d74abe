// What a run of a mechanism with closed loops will do, decided before it starts: the
// formulation (and why), the rank of the loop constraints and the mechanism's mobility, and
// the assembled initial state (Newton near the given pose, prescribed joints on their track).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "server/drives/drive_set.h"
#include "server/kinematics/loop_solver.h"
#include "server/model/loop_closure.h"
#include "server/model/model.h"
#include "server/sim/formulation_choice.h"
#include "server/sim/run_config.h"

namespace mbstream {

struct LoopPlan {
  FormulationChoice choice;
  LoopRank rank;                 // of the loop constraints at the assembled pose
  Eigen::VectorXd q0, qd0;       // assembled (nq, nv): phi(q0) = 0, G qd0 = 0, prescribed on track
  int assembly_iterations = 0;   // Newton iterations (0: the given pose was assembled)
  double assembly_change = 0.0;  // largest |q0 - given q| (rad or m)
  std::string assembly;          // one sentence for the user
};

// Validates a run of `model` closed by `loops` and assembles its initial state. Throws
// InputError, saying what to do, for what the loops cannot run: velocity-source drives, an accuracy
// target, prescribed joints that the loops already determine, formulation kinematic without every
// degree of freedom prescribed, and a loop that cannot close near the given pose (its joint named
// with FILE:LINE). Formulation joint with method ida is the index-2 GGL DAE (closed_loop_dae.h),
// with an ODE method the Baumgarte ODE (closed_loop_ode.h); the body formulations take the cut
// joints as more joints (server/body/body_cuts.h).
LoopPlan PlanLoopRun(const Model& model, const std::vector<LoopClosure>& loops,
                     const RunConfig& config, const DriveSet& drives);

// The Newton tolerance of the assembly and of each kinematic frame (m or rad).
inline constexpr double kLoopAssemblyTolerance = 1e-12;

}  // namespace mbstream
