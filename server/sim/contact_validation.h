// The run's contact settings at the door (ValidateRun; docs/contact.md): their ranges, the
// filter's names against the model, and what contact does not run with yet.
#pragma once

#include <string>
#include <vector>

#include "server/model/loop_closure.h"
#include "server/model/model.h"
#include "server/sim/run_config.h"

namespace mbstream {

// The ranges the spec's edge gives too (absurd values are refused, not clamped):
inline constexpr double kMaxContactStiffness = 1e12;   // N/m
inline constexpr double kMaxContactDissipation = 1e4;  // s/m
inline constexpr double kMaxFrictionCoefficient = 100.0;
inline constexpr double kMinStictionTolerance = 1e-9;   // m/s
inline constexpr double kMaxStictionTolerance = 100.0;  // m/s
inline constexpr double kMaxHertzModulus = 1e13;        // Pa (diamond's E* is 6e11)

// Throws InputError "contact.FIELD: what; what to do" for a stiffness that is not finite or
// not in (0, kMaxContactStiffness], a dissipation outside [0, kMaxContactDissipation], a
// friction coefficient outside [0, kMaxFrictionCoefficient] or mu_dynamic > mu_static, a
// stiction tolerance outside [kMinStictionTolerance, kMaxStictionTolerance], a Hertz modulus
// outside [0, kMaxHertzModulus], a filter name
// that is neither a link nor a collision of the model; and, when the model's geometry may
// touch, for a body formulation, or closed loops with method ida (contact runs in formulation
// joint with an ODE method, the tree's and the closed loops').
void CheckContact(const Model& model, const RunConfig& config,
                  const std::vector<LoopClosure>& loops = {});

}  // namespace mbstream
