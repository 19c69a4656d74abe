// Module Title Points i x y z ... Polygons (i j k ...) ...;
#include <map>
#include <set>
#include <string>

#include "viewer/script/command_parsers.h"

namespace mbstream::scene_script {

namespace {

std::string IdRange(const std::map<int, SourcePosition>& ids) {
  if (ids.empty()) return "none";
  return std::to_string(ids.begin()->first) + ".." + std::to_string(ids.rbegin()->first);
}

}  // namespace

PartCommand ParseModule(TokenStream& in, const Token& keyword) {
  PartCommand part;
  part.position = keyword.position;
  part.keyword = "Module";
  const Token& name = in.ExpectWord("the module's name after 'Module'");
  part.name = name.text;
  part.name_position = name.position;
  ModuleShape module;
  std::map<int, SourcePosition> ids;
  in.ExpectKeyword("points", "after the module's name");
  while (in.PeekIs(TokenKind::kNumber)) {
    const Token& id_token = in.Peek();
    const int id = in.ExpectInteger("a point number", 0);
    Eigen::Vector3d p;
    for (int i = 0; i < 3; ++i) {
      p[i] = in.ExpectNumber("the point's x y z after its number " + std::to_string(id));
    }
    if (const auto it = ids.find(id); it != ids.end()) {
      in.Error(id_token, "point " + std::to_string(id) + " is defined twice (first at line " +
                             std::to_string(it->second.line) + "); number each point once");
      continue;
    }
    ids[id] = id_token.position;
    module.point_ids.push_back(id);
    module.points.push_back(p);
  }
  in.ExpectKeyword("polygons", "after the module's points (Points i x y z ...)");
  while (!in.Accept(TokenKind::kSemicolon)) {
    const Token& open = in.Peek();
    in.Expect(TokenKind::kLeftParen, "'(' starting a polygon, or ';' ending the Module");
    std::vector<int> polygon;
    std::set<int> distinct;
    while (!in.Accept(TokenKind::kRightParen)) {
      if (in.Accept(TokenKind::kComma)) continue;
      const Token& index = in.Peek();
      const int id = in.ExpectInteger("a point number or ')' in the polygon", 0);
      if (!ids.contains(id)) {
        in.Error(index, "polygon uses point " + std::to_string(id) +
                            ", which Points does not define (it defines " + IdRange(ids) + ")");
      }
      polygon.push_back(id);
      distinct.insert(id);
    }
    if (distinct.size() < 3) {
      in.Error(open, "a polygon needs at least 3 different points, this one has " +
                         std::to_string(distinct.size()));
    }
    module.polygons.push_back(std::move(polygon));
  }
  if (module.polygons.empty()) {
    in.Error(name, "Module '" + part.name + "' has no polygons; list faces as (i j k ...)");
  }
  part.shape = module;
  return part;
}

}  // namespace mbstream::scene_script
