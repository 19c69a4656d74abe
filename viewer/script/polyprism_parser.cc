// Polyprism Title Height h x1 y1 x2 y2 ... Arc [Large] [to] x y radius r [res n] ...;
#include <string>

#include "viewer/script/command_parsers.h"

namespace mbstream::scene_script {

namespace {

constexpr int kDefaultArcResolution = 16;
constexpr int kMaxArcResolution = 512;

PolyprismStep ParseArc(TokenStream& in, const Token& keyword) {
  PolyprismStep step;
  step.position = keyword.position;
  step.arc = true;
  step.large = in.AcceptKeyword("large");
  in.AcceptKeyword("to");
  step.to.x() = in.ExpectNumber("the arc's end point x y after 'Arc'");
  step.to.y() = in.ExpectNumber("the arc's end point y");
  in.ExpectKeyword("radius", "and the arc's radius after its end point");
  const Token& radius = in.Peek();
  step.radius = in.ExpectNumber("the arc's radius (mm; > 0 clockwise, < 0 anticlockwise)");
  if (step.radius == 0) {
    in.Error(radius, "the arc's radius is 0; give > 0 for clockwise, < 0 for anticlockwise");
  }
  step.resolution = kDefaultArcResolution;
  if (in.AcceptKeyword("res") || in.AcceptKeyword("resolution")) {
    step.resolution =
        in.ExpectInteger("the arc's resolution (segments) after 'res'", 1, kMaxArcResolution);
  }
  return step;
}

}  // namespace

PartCommand ParsePolyprism(TokenStream& in, const Token& keyword) {
  PartCommand part;
  part.position = keyword.position;
  part.keyword = "Polyprism";
  const Token& name = in.ExpectWord("the polyprism's name after 'Polyprism'");
  part.name = name.text;
  part.name_position = name.position;
  PolyprismShape prism;
  in.ExpectKeyword("height", "and the prism's height after its name");
  prism.height = in.ExpectPositive("the prism's height (mm) after 'Height'");
  while (!in.Accept(TokenKind::kSemicolon)) {
    const Token& token = in.Peek();
    if (in.AcceptKeyword("arc")) {
      if (prism.steps.empty()) {
        in.Fail(token,
                "a Polyprism outline starts with a point 'x y', not an Arc; "
                "write the arc's start point first");
      }
      prism.steps.push_back(ParseArc(in, token));
      continue;
    }
    if (token.kind != TokenKind::kNumber) {
      in.FailExpected(token,
                      "an outline point 'x y', 'Arc' or ';' in Polyprism '" + part.name + "'");
    }
    PolyprismStep step;
    step.position = token.position;
    step.to.x() = in.Next().number;
    step.to.y() = in.ExpectNumber("the point's y after its x in Polyprism '" + part.name + "'");
    prism.steps.push_back(step);
  }
  if (prism.steps.size() < 3) {
    in.Error(name, "Polyprism '" + part.name + "' has " + std::to_string(prism.steps.size()) +
                       " outline points; it needs at least 3");
  }
  part.shape = prism;
  return part;
}

}  // namespace mbstream::scene_script
