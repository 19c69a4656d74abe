// A run's contact, as every formulation with contact forces sets it up and sums it up (the
// tree's and the closed loops' joint-space runs, body-baumgarte): why it is on or off, the
// contact log of the output frames, the summary and the failure note.
#pragma once

#include <string>

#include "server/contact/contact_forces.h"
#include "server/model/model.h"
#include "server/sim/contact_log.h"
#include "server/sim/run_result.h"

namespace mbstream {

// Appends to stats->formulation_reason why contact is on (`contact` not null: the pairs that
// may touch and the step cap, s) or off (docs/contact.md).
void AddContactReason(const Model& model, const ContactSettings& settings,
                      const ContactForces* contact, double max_step, RunStats* stats);

// Starts `log` for `contact` (nothing when null): every frame's records, or the latest frame's
// alone when `sink` keeps the frames itself.
void StartContactLog(const ContactForces* contact, const FrameSink* sink, ContactLog* log);

// After the frames: RunStats.contact from an active log, and its deep-contact warning.
void FinishContactLog(const ContactLog& log, RunStats* stats);

// For a run that failed: the deepest contact of the last evaluation, by pair, and what to try
// (the failure path only: it allocates).
std::string DeepestContactNote(const ContactForces& contact);

}  // namespace mbstream
