// The choice and its verification as the JSON object of stats.json's "choice": the
// candidates with the numbers that decided (pilot errors and steps, growth, stiffness,
// predicted tolerance and CPU time), the pick and why, the check and what it measured, and
// the CPU time of each phase.
#pragma once

#include <string>

#include "server/choose/method_choice.h"
#include "server/choose/verification.h"

namespace mbstream {

// `run`: the chosen run's own statistics (its CPU time, where it continued a pilot).
std::string ChoiceJson(const RunConfig& asked, const MethodChoice& choice,
                       const Verification& verification, const RunStats& run);

}  // namespace mbstream
