#include "shared/model_files/urdf_outline.h"

#include <tinyxml.h>

#include <string_view>

#include "shared/model_files/xml_shape.h"

namespace mbstream::model_files {

namespace {

std::string AttributeOf(const TiXmlElement& element, const char* name) {
  const char* value = element.Attribute(name);
  return value == nullptr ? std::string() : std::string(value);
}

// The <geometry><mesh filename> of every `part` element (visual or collision) of `link`.
void NoteMeshes(const TiXmlElement& link, const char* part, std::vector<std::string>* meshes) {
  for (const TiXmlElement* e = link.FirstChildElement(part); e != nullptr;
       e = e->NextSiblingElement(part)) {
    const TiXmlElement* geometry = e->FirstChildElement("geometry");
    const TiXmlElement* mesh = geometry == nullptr ? nullptr : geometry->FirstChildElement("mesh");
    if (mesh != nullptr && mesh->Attribute("filename") != nullptr) {
      meshes->push_back(AttributeOf(*mesh, "filename"));
    }
  }
}

void NoteMaterial(const TiXmlElement& material, UrdfOutline* outline) {
  const std::string name = AttributeOf(material, "name");
  if (!name.empty() && material.FirstChildElement("color") != nullptr) {
    outline->coloured_materials.insert(name);
  }
}

}  // namespace

std::optional<UrdfOutline> ReadUrdfOutline(const std::string& text, std::string* error) {
  if (const auto problem = CheckXmlShape(text, XmlShapeLimits{})) {
    *error = "line " + std::to_string(problem->line) + ": " + problem->what;
    return std::nullopt;
  }
  TiXmlDocument document;
  document.Parse(text.c_str(), nullptr, TIXML_ENCODING_UTF8);
  if (document.Error()) {
    *error = "the XML is not well formed (line " + std::to_string(document.ErrorRow()) + ": " +
             document.ErrorDesc() + ")";
    return std::nullopt;
  }
  TiXmlElement* robot = document.FirstChildElement("robot");
  if (robot == nullptr) {
    *error = "no <robot> element at the top level";
    return std::nullopt;
  }
  UrdfOutline outline;
  for (TiXmlElement* e = robot->FirstChildElement(); e != nullptr; e = e->NextSiblingElement()) {
    const std::string_view tag = e->Value();
    if (tag == "material") NoteMaterial(*e, &outline);
    if (tag == "link") {
      outline.link_order.push_back(AttributeOf(*e, "name"));
      NoteMeshes(*e, "visual", &outline.visual_meshes);
      NoteMeshes(*e, "collision", &outline.collision_meshes);
      for (const TiXmlElement* visual = e->FirstChildElement("visual"); visual != nullptr;
           visual = visual->NextSiblingElement("visual")) {
        if (const TiXmlElement* material = visual->FirstChildElement("material")) {
          NoteMaterial(*material, &outline);
        }
      }
    }
    if (tag == "joint") {
      const std::string name = AttributeOf(*e, "name");
      outline.joint_order.push_back(name);
      if (AttributeOf(*e, "type") == "revolute" && e->FirstChildElement("limit") == nullptr) {
        e->SetAttribute("type", "continuous");
        outline.limitless_revolute_joints.push_back(name);
      }
    }
  }
  if (outline.limitless_revolute_joints.empty()) {
    outline.urdfdom_text = text;
  } else {
    TiXmlPrinter printer;
    document.Accept(&printer);
    outline.urdfdom_text = printer.Str();
  }
  return outline;
}

}  // namespace mbstream::model_files
