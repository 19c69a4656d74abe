// The first pass over a URDF: TinyXML (the XML parser urdfdom itself uses on Debian
// bookworm) reads the text to learn what urdfdom does not report: the line of every link
// and joint, duplicate names (which urdfdom rejects without saying where), links with two
// parent joints (which urdfdom silently accepts), and mbstream's extension elements.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace mbstream {

struct UrdfXmlFacts {
  std::map<std::string, int> link_lines;        // name -> line of its <link>
  std::map<std::string, int> joint_lines;       // name -> line of its <joint>
  std::vector<std::string> link_order;          // link names in document order
  std::vector<std::string> joint_order;         // joint names in document order
  std::map<std::string, double> rotor_inertia;  // joint name -> kg*m^2 (or kg if prismatic)
  std::vector<std::string> mesh_files;          // every visual/collision <mesh filename>
  std::string urdfdom_text;                     // the XML to hand to urdfdom
};

// Scans URDF XML `text` (`source` names it in messages). Throws InputError if the text's
// shape is beyond shared/model_files/xml_shape.h's limits (checked before TinyXML walks it; more
// than `max_links` <link> elements when > 0), the XML is not well formed, has no <robot>, repeats a
// link or joint name, gives a link two parent joints, or has a bad <mbstream:rotor_inertia>. A
// revolute joint without <limit> (which urdfdom rejects) is rewritten in urdfdom_text as
// continuous, with a warning.
UrdfXmlFacts ScanUrdfXml(const std::string& text, const std::string& source,
                         std::vector<std::string>* warnings, int max_links = 0);

}  // namespace mbstream
