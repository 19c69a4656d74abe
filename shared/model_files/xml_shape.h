// The shape of an XML document checked before any XML parser walks it: TinyXML (under
// urdfdom) parses recursively, keeps an element's attributes in a list it searches on every
// insertion, and expands nothing it is not told of. So a document nested 200,000 deep
// overflows the stack, 100,000 attributes on one element take minutes, and a UTF-16 file or
// a DOCTYPE with entities fails with a misleading message. One linear pass over the text
// finds all of these first and names the line (docs/reliability.md, "Limits").
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace mbstream::model_files {

struct XmlShapeLimits {
  int max_depth = 64;            // element nesting (a URDF needs 5: robot/link/visual/...)
  int max_attributes = 256;      // attributes of one element (a URDF element has at most 6)
  long max_elements = 200'000;   // elements in the document (a PR2 has about 6,000)
  long max_top_links = 100'000;  // <link> children of the root element (callers lower it)
  // Count <link> elements at any depth against max_top_links (SDFormat: links sit in a
  // <model>, itself perhaps in a <world>), not only the root's children (URDF).
  bool links_at_any_depth = false;
  // Said with a nesting over max_depth: how deep the format nests.
  std::string_view nesting_note = "a URDF nests 5 deep (robot, link, visual, geometry, mesh)";
  // An element refused wherever it stands (empty: none), and what to do instead. SDFormat's
  // <include> makes the parser read another file: on the server, a file of the server's.
  std::string_view refused_element;
  std::string_view refused_note;
};

struct XmlShape {
  int depth = 0;        // the deepest nesting seen
  long elements = 0;    // elements seen
  long top_links = 0;   // <link> elements directly under the root (any depth: see limits)
  long top_joints = 0;  // <joint> elements directly under the root element
};

struct XmlShapeProblem {
  int line = 1;                    // 1-based line of `text` where the problem is
  std::string what;                // what is wrong; what to do
  bool over_caller_limit = false;  // more <link> elements than max_top_links (else a defect)
};

// What is wrong with the shape of `text`, or nullopt when it is within `limits` (its counts
// in `*shape` if given). Checked: UTF-16 or UTF-32 text (a
// byte-order mark or NUL bytes), bytes that are not UTF-8, a DOCTYPE that declares entities,
// and the limits. Not checked: well-formedness (the parser's job after this).
std::optional<XmlShapeProblem> CheckXmlShape(std::string_view text, const XmlShapeLimits& limits,
                                             XmlShape* shape = nullptr);

}  // namespace mbstream::model_files
