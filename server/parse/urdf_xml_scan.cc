#include "server/parse/urdf_xml_scan.h"

#include <tinyxml.h>

#include <algorithm>
#include <cmath>
#include <string_view>
#include <utility>

#include "server/parse/import_cancel.h"
#include "server/parse/urdf_diagnostics.h"
#include "shared/common/check.h"
#include "shared/model_files/xml_shape.h"

namespace mbstream {

namespace {

constexpr std::string_view kExtensionPrefix = "mbstream:";

std::string AttributeOf(const TiXmlElement& element, const char* name) {
  const char* value = element.Attribute(name);
  return value == nullptr ? std::string() : std::string(value);
}

class Scanner {
 public:
  Scanner(const std::string& source, std::vector<std::string>* warnings)
      : source_(source), warnings_(warnings) {}

  void ScanLink(const TiXmlElement& link) {
    const std::string name = NameOf(link, "link");
    if (!Record(name, link.Row(), "link", facts_.link_lines)) return;
    facts_.link_order.push_back(name);
    for (const char* part : {"visual", "collision"}) {
      for (const TiXmlElement* e = link.FirstChildElement(part); e != nullptr;
           e = e->NextSiblingElement(part)) {
        const TiXmlElement* geometry = e->FirstChildElement("geometry");
        const TiXmlElement* mesh =
            geometry == nullptr ? nullptr : geometry->FirstChildElement("mesh");
        if (mesh != nullptr && mesh->Attribute("filename") != nullptr) {
          facts_.mesh_files.push_back(AttributeOf(*mesh, "filename"));
        }
      }
    }
  }

  // Returns true if the joint was rewritten for urdfdom.
  bool ScanJoint(TiXmlElement& joint) {
    const std::string name = NameOf(joint, "joint");
    const int line = joint.Row();
    if (!Record(name, line, "joint", facts_.joint_lines)) return false;
    facts_.joint_order.push_back(name);
    const std::string where = Where(source_, line, "joint", name);
    const std::string type = AttributeOf(joint, "type");

    const TiXmlElement* child = joint.FirstChildElement("child");
    const std::string child_link = child == nullptr ? "" : AttributeOf(*child, "link");
    if (!child_link.empty()) {
      const auto [it, inserted] = parent_joint_.emplace(child_link, std::make_pair(name, line));
      if (!inserted) {
        throw InputError(where + ": link '" + child_link + "' already has a parent joint, '" +
                         it->second.first + "' (line " + std::to_string(it->second.second) +
                         "); a link with two parents closes a kinematic loop, and mbstream "
                         "simulates trees only: remove one of the two joints");
      }
    }

    for (const TiXmlElement* e = joint.FirstChildElement(); e != nullptr;
         e = e->NextSiblingElement()) {
      const std::string tag = e->Value();
      if (tag.rfind(kExtensionPrefix, 0) != 0) continue;
      if (tag != "mbstream:rotor_inertia") {
        Warn(where + ": unknown extension <" + tag + "> is ignored; mbstream knows " +
             "<mbstream:rotor_inertia value=\"...\"/>");
      } else if (type == "fixed") {
        Warn(where + ": <mbstream:rotor_inertia> on a fixed joint is ignored");
      } else {
        facts_.rotor_inertia[name] = RotorInertia(*e, where);
      }
    }

    if (type == "revolute" && joint.FirstChildElement("limit") == nullptr) {
      Warn(where + ": revolute joint has no <limit>; imported without position, velocity " +
           "and effort limits, like type=\"continuous\"; add <limit lower=\"...\" " +
           "upper=\"...\" effort=\"...\" velocity=\"...\"/> (rad, N*m, rad/s) or write " +
           "type=\"continuous\"");
      joint.SetAttribute("type", "continuous");
      return true;
    }
    return false;
  }

  UrdfXmlFacts& facts() { return facts_; }

 private:
  // The element's name attribute ("" when absent: urdfdom reports that in its words). A name
  // that is empty or holds a control character (TinyXML reads "&#0;" as an empty name) is refused:
  // results and messages quote names, and urdfdom would take "" without a word.
  std::string NameOf(const TiXmlElement& element, const char* kind) const {
    const char* value = element.Attribute("name");
    if (value == nullptr) return "";
    const std::string name(value);
    const bool control = std::any_of(name.begin(), name.end(),
                                     [](char c) { return static_cast<unsigned char>(c) < 0x20; });
    if (name.empty() || control) {
      throw InputError(source_ + ":" + std::to_string(element.Row()) + ": " + kind + " name " +
                       (name.empty() ? "is empty" : "holds a control character (e.g. &#0;)") +
                       "; give every " + kind + " a unique printable name");
    }
    return name;
  }

  // Records `name` at `line`; false when the name is missing (urdfdom reports that).
  bool Record(const std::string& name, int line, const char* kind,
              std::map<std::string, int>& lines) {
    if (name.empty()) return false;
    const auto [it, inserted] = lines.emplace(name, line);
    if (!inserted) {
      throw InputError(Where(source_, line, kind, name) +
                       ": the name is used twice (first on line " + std::to_string(it->second) +
                       "); give every " + kind + " a unique name");
    }
    return true;
  }

  double RotorInertia(const TiXmlElement& element, const std::string& where) const {
    double value = 0.0;
    if (element.QueryDoubleAttribute("value", &value) != TIXML_SUCCESS) {
      throw InputError(where + ": <mbstream:rotor_inertia> needs a numeric value attribute; " +
                       "write e.g. <mbstream:rotor_inertia value=\"0.01\"/> (kg*m^2, or kg " +
                       "for a prismatic joint)");
    }
    if (!std::isfinite(value) || value < 0.0) {
      throw InputError(where + ": rotor inertia " + FormatNumber(value) +
                       " is not a finite number >= 0; give the reflected rotor inertia " +
                       "(kg*m^2, or kg for a prismatic joint), or 0");
    }
    return value;
  }

  void Warn(std::string message) { warnings_->push_back(std::move(message)); }

  const std::string& source_;
  std::vector<std::string>* warnings_;
  UrdfXmlFacts facts_;
  std::map<std::string, std::pair<std::string, int>> parent_joint_;  // child -> joint, line
};

}  // namespace

UrdfXmlFacts ScanUrdfXml(const std::string& text, const std::string& source,
                         std::vector<std::string>* warnings, int max_links) {
  MBSTREAM_CHECK(warnings != nullptr);
  model_files::XmlShapeLimits limits;
  if (max_links > 0) limits.max_top_links = max_links;
  if (const auto problem = model_files::CheckXmlShape(text, limits)) {
    const std::string message = source + ":" + std::to_string(problem->line) + ": " + problem->what;
    if (problem->over_caller_limit) throw LimitError(message);
    throw InputError(message);
  }
  TiXmlDocument document;
  document.Parse(text.c_str(), nullptr, TIXML_ENCODING_UTF8);
  if (document.Error()) {
    if (document.ErrorId() == TiXmlBase::TIXML_ERROR_DOCUMENT_EMPTY) {
      throw InputError(source + ": the file is empty; give a URDF: a <robot name=\"...\"> " +
                       "element holding <link> and <joint> elements");
    }
    throw InputError(source + ":" + std::to_string(document.ErrorRow()) +
                     ": the XML is not well formed (" + document.ErrorDesc() +
                     "), so urdfdom cannot parse it; fix the markup at or before this line");
  }
  TiXmlElement* robot = document.FirstChildElement("robot");
  if (robot == nullptr) {
    throw InputError(source + ": no <robot> element at the top level; a URDF is a " +
                     "<robot name=\"...\"> element holding <link> and <joint> elements");
  }

  Scanner scanner(source, warnings);
  bool rewritten = false;
  ImportCancelPoll poll;  // import_cancel.h
  for (TiXmlElement* e = robot->FirstChildElement(); e != nullptr; e = e->NextSiblingElement()) {
    poll.Tick();
    const std::string_view tag = e->Value();
    if (tag == "link") scanner.ScanLink(*e);
    if (tag == "joint") rewritten = scanner.ScanJoint(*e) || rewritten;
  }

  UrdfXmlFacts& facts = scanner.facts();
  if (rewritten) {
    TiXmlPrinter printer;
    document.Accept(&printer);
    facts.urdfdom_text = printer.Str();
  } else {
    facts.urdfdom_text = text;
  }
  return std::move(facts);
}

}  // namespace mbstream
