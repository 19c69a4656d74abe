// A run's contacts between the core's ContactLog (contact_log.h) and the wire's
// Frame.contacts (frame.proto's FrameContact: link names, world-frame points, normals and
// forces in SI units).
#pragma once

#include <vector>

#include "mbstream/v1/frame.pb.h"
#include "server/sim/contact_log.h"

namespace mbstream {

// The contacts `log` holds for the output frame at time `t` (its records at t: every frame's
// when it keeps them, else the latest frame's) into `out`, whose elements are reused (no
// allocation once they have grown). Every number must be finite: a non-finite one is a bug
// and throws InternalError.
void ContactsToProto(const ContactLog& log, double t,
                     google::protobuf::RepeatedPtrField<v1::FrameContact>* out);

// A run's contacts rebuilt from its stored frames (the inverse of ContactsToProto over every
// frame): `log` keeps every frame's records, its geometries are the (link, collision) pairs
// the contacts name, in order of appearance. `active` says the run had contact (its
// RunStats.contact); frames without contacts then give a log with no records.
void ContactsFromFrames(const std::vector<v1::Frame>& frames, bool active, ContactLog* log);

}  // namespace mbstream
