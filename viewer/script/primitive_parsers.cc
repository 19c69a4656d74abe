// Cylinder, Cone, Cube, Sphere and Part (STL).
#include <string>

#include "viewer/script/command_parsers.h"
#include "viewer/script/name_suggestion.h"

namespace mbstream::scene_script {

namespace {

constexpr int kDefaultResolution = 24;
constexpr int kMaxResolution = 512;

PartCommand StartPart(TokenStream& in, const Token& keyword, std::string canonical) {
  PartCommand part;
  part.position = keyword.position;
  part.keyword = std::move(canonical);
  const Token& name = in.ExpectWord("the " + part.keyword + "'s name after '" + keyword.text + "'");
  part.name = name.text;
  part.name_position = name.position;
  return part;
}

// `dia D res N len L` (any order) up to ';'. `radius` replaces `dia` for a sphere.
struct SizeWords {
  std::optional<double> dia;
  std::optional<double> radius;
  std::optional<int> res;
  std::optional<double> len;
};

SizeWords ParseSizeWords(TokenStream& in, const PartCommand& part, bool sphere) {
  SizeWords words;
  const std::string command = part.keyword + " '" + part.name + "'";
  const std::vector<std::string> allowed = sphere ? std::vector<std::string>{"radius", "res"}
                                                  : std::vector<std::string>{"dia", "res", "len"};
  while (!in.Accept(TokenKind::kSemicolon)) {
    const Token& token = in.Peek();
    if (!sphere && (in.AcceptKeyword("dia") || in.AcceptKeyword("diameter"))) {
      words.dia = in.ExpectPositive("the diameter (mm) after '" + token.text + "'");
    } else if (sphere && in.AcceptKeyword("radius")) {
      words.radius = in.ExpectPositive("the radius (mm) after 'radius'");
    } else if (in.AcceptKeyword("res") || in.AcceptKeyword("resolution")) {
      words.res = in.ExpectInteger(
          "the resolution (number of sides, at least 3) after '" + token.text + "'", 3,
          kMaxResolution);
    } else if (!sphere && (in.AcceptKeyword("len") || in.AcceptKeyword("length"))) {
      words.len = in.ExpectPositive("the length (mm) after '" + token.text + "'");
    } else {
      std::string list;
      for (size_t i = 0; i < allowed.size(); ++i) {
        list += (i == 0 ? "" : i + 1 == allowed.size() ? " or " : ", ") + allowed[i];
      }
      std::vector<std::string> spellings = allowed;
      spellings.insert(spellings.end(), {"resolution"});
      if (!sphere) spellings.insert(spellings.end(), {"diameter", "length"});
      const std::string hint =
          token.kind == TokenKind::kWord ? DidYouMean(token.text, spellings) : "";
      in.Fail(token,
              "expected " + list + " or ';' in " + command + ", found " + Describe(token) + hint);
    }
  }
  return words;
}

void RequireSize(TokenStream& in, const PartCommand& part, bool present, std::string_view what) {
  if (present) return;
  Token at;
  at.position = part.name_position;
  in.Error(at, part.keyword + " '" + part.name + "' has no " + std::string(what) + "; add it");
}

// `Center x . y . z .` or `Direction x . y . z .` inside the cone's clause.
Eigen::Vector3d ParseVector(TokenStream& in, std::string_view after) {
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  int axis = 0;
  double value = 0;
  bool any = false;
  while (in.AcceptAxisValue(&axis, &value)) {
    v[axis] = value;
    any = true;
  }
  if (!any) in.FailExpected(in.Peek(), "x, y or z values after '" + std::string(after) + "'");
  return v;
}

}  // namespace

PartCommand ParseCylinder(TokenStream& in, const Token& keyword) {
  PartCommand part = StartPart(in, keyword, "Cylinder");
  const SizeWords words = ParseSizeWords(in, part, false);
  RequireSize(in, part, words.dia.has_value(), "diameter ('dia D', mm)");
  RequireSize(in, part, words.len.has_value(), "length ('len L', mm)");
  part.shape = CylinderShape{words.dia.value_or(1), words.res.value_or(kDefaultResolution),
                             words.len.value_or(1)};
  return part;
}

PartCommand ParseCone(TokenStream& in, const Token& keyword) {
  PartCommand part = StartPart(in, keyword, "Cone");
  ConeShape cone;
  if (in.Accept(TokenKind::kLeftParen)) {
    while (!in.Accept(TokenKind::kRightParen)) {
      const Token& token = in.Peek();
      if (in.AcceptKeyword("center") || in.AcceptKeyword("centre")) {
        cone.center = ParseVector(in, token.text);
      } else if (in.AcceptKeyword("direction")) {
        const Eigen::Vector3d direction = ParseVector(in, token.text);
        if (direction.norm() < 1e-12) {
          in.Error(token, "the cone's Direction is zero; give the apex direction, e.g. z 1");
        } else {
          cone.direction = direction.normalized();
        }
      } else {
        in.FailExpected(token, "Center, Direction or ')' in the cone's clause");
      }
    }
  }
  const SizeWords words = ParseSizeWords(in, part, false);
  RequireSize(in, part, words.dia.has_value(), "base diameter ('dia D', mm)");
  RequireSize(in, part, words.len.has_value(), "height ('len H', mm)");
  cone.diameter = words.dia.value_or(1);
  cone.resolution = words.res.value_or(kDefaultResolution);
  cone.length = words.len.value_or(1);
  part.shape = cone;
  return part;
}

PartCommand ParseCube(TokenStream& in, const Token& keyword) {
  PartCommand part = StartPart(in, keyword, "Cube");
  CubeShape cube;
  const char* names[] = {"xLen", "yLen", "zLen"};
  for (int i = 0; i < 3; ++i) {
    cube.size[i] = in.ExpectPositive("the cube's " + std::string(names[i]) + " (mm)");
  }
  ExpectEndOfCommand(in, "the Cube command");
  part.shape = cube;
  return part;
}

PartCommand ParseSphere(TokenStream& in, const Token& keyword) {
  PartCommand part = StartPart(in, keyword, "Sphere");
  const SizeWords words = ParseSizeWords(in, part, true);
  RequireSize(in, part, words.radius.has_value(), "radius ('radius R', mm)");
  part.shape = SphereShape{words.radius.value_or(1), words.res.value_or(kDefaultResolution)};
  return part;
}

PartCommand ParseStlPart(TokenStream& in, const Token& keyword) {
  PartCommand part = StartPart(in, keyword, "Part");
  part.shape = StlShape{part.name, {}};
  ExpectEndOfCommand(in, "the Part command (Part FileName;)");
  return part;
}

}  // namespace mbstream::scene_script
