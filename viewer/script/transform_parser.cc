// The transform clause `(Shift x X y Y z Z Euler E1 E2 E3 [LBox L])` and command endings.
#include <array>
#include <string>

#include "viewer/script/command_parsers.h"

namespace mbstream::scene_script {

namespace {

std::string PositionText(SourcePosition p) {
  return std::to_string(p.line) + ":" + std::to_string(p.column);
}

}  // namespace

std::optional<TransformClause> AcceptTransformClause(TokenStream& in, std::optional<double>* lbox) {
  if (!in.PeekIs(TokenKind::kLeftParen)) return std::nullopt;
  TransformClause clause;
  clause.position = in.Next().position;
  std::array<bool, 3> axis_seen{};
  bool euler_seen = false;
  const std::string items = lbox ? "x, y, z, shift, euler or lbox" : "x, y, z, shift or euler";
  while (!in.Accept(TokenKind::kRightParen)) {
    const Token& token = in.Peek();
    int axis = 0;
    double value = 0;
    if (in.AcceptKeyword("shift")) continue;
    if (in.AcceptAxisValue(&axis, &value)) {
      if (axis_seen[axis]) {
        in.Error(token, std::string(1, static_cast<char>('x' + axis)) +
                            " is given twice in one transform; keep one value");
      }
      axis_seen[axis] = true;
      clause.shift_mm[axis] = value;
      continue;
    }
    if (in.AcceptKeyword("euler")) {
      if (euler_seen) in.Error(token, "euler is given twice in one transform; keep one");
      euler_seen = true;
      for (int i = 0; i < 3; ++i) {
        clause.euler_deg[i] = in.ExpectNumber("three Euler angles (degrees) after 'euler'");
      }
      continue;
    }
    if (lbox && in.AcceptKeyword("lbox")) {
      *lbox = in.ExpectPositive("the scene box size (mm) after 'lbox'");
      continue;
    }
    if (token.kind == TokenKind::kSemicolon || token.kind == TokenKind::kEnd) {
      in.FailExpected(token,
                      "')' closing the transform opened at " + PositionText(clause.position));
    }
    in.FailExpected(token, items + " in a transform");
  }
  return clause;
}

void ExpectEndOfCommand(TokenStream& in, std::string_view command) {
  if (in.Accept(TokenKind::kSemicolon)) return;
  in.FailExpected(in.Peek(), "';' ending " + std::string(command), "every command ends with ';'");
}

}  // namespace mbstream::scene_script
