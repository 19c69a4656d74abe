// The run spec's `contact` section (proto/mbstream/v1/run_spec.proto, docs/contact.md) to the
// physics core's ContactSettings and back. The ranges are ValidateRun's
// (server/sim/contact_validation.h); this edge refuses non-finite values and empty or
// overlong names, naming the field.
#pragma once

#include <string>

#include "mbstream/v1/run_spec.pb.h"
#include "server/contact/contact_settings.h"

namespace mbstream {

// Throws InputError "<source>: contact.FIELD: ...".
ContactSettings ToContactSettings(const v1::Contact& spec, const std::string& source);

// Every field written (the defaults too), for a spec that round-trips.
void ToContactSpec(const ContactSettings& settings, v1::Contact* spec);

}  // namespace mbstream
