// The shape of a run spec's JSON text, checked before protobuf's JSON parser reads it: that
// parser reads a null inside a list of numbers, and a list inside one, as zeros; cuts a
// string at a NUL (\u0000); and echoes an unknown key of any length in its message.
#pragma once

#include <string>

namespace mbstream {

// Throws InputError "<source>: <where>: <problem>; <what to do>" for text that is not UTF-8,
// nested deeper than 32, a key longer than 200 bytes (quoted cut at 200), a null or a list
// inside a list, or a string holding a NUL. Well-formedness and field names are left to
// protobuf's parser.
void CheckJsonShape(const std::string& json, const std::string& source);

// `text` cut to at most `bytes` bytes (on a UTF-8 boundary) with "..." when cut.
std::string CutForMessage(const std::string& text, std::size_t bytes = 200);

}  // namespace mbstream
