// One parser per command. Each starts just after the command's keyword (`keyword` is that
// token) and reads up to and including the closing ';'. Errors are recorded in the stream;
// an error that stops the command throws CommandAbort.
#pragma once

#include <optional>

#include "viewer/script/commands.h"
#include "viewer/script/token_stream.h"

namespace mbstream::scene_script {

// A transform clause when the next token is '(' (else nullopt, nothing consumed). `lbox`
// non-null allows `LBox n` inside it (the Device's clause).
std::optional<TransformClause> AcceptTransformClause(TokenStream& in,
                                                     std::optional<double>* lbox = nullptr);

// Expects ';' ending the command `command` ("the Cube command").
void ExpectEndOfCommand(TokenStream& in, std::string_view command);

DeviceCommand ParseDevice(TokenStream& in, const Token& keyword);

PartCommand ParseCylinder(TokenStream& in, const Token& keyword);
PartCommand ParseCone(TokenStream& in, const Token& keyword);
PartCommand ParseCube(TokenStream& in, const Token& keyword);
PartCommand ParseSphere(TokenStream& in, const Token& keyword);
PartCommand ParseStlPart(TokenStream& in, const Token& keyword);
PartCommand ParsePolyprism(TokenStream& in, const Token& keyword);
PartCommand ParseModule(TokenStream& in, const Token& keyword);

SetCommand ParseSet(TokenStream& in, const Token& keyword);
RenderCommand ParseRender(TokenStream& in, const Token& keyword);
ProbeCommand ParseProbe(TokenStream& in, const Token& keyword);

}  // namespace mbstream::scene_script
