#include "shared/model_files/tcp_choice.h"

#include <algorithm>
#include <cctype>
#include <map>

namespace mbstream::model_files {

namespace {

std::string Lowercase(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

}  // namespace

std::string LastMovingLink(const JointOrder& order) {
  std::string last;
  for (const auto& joint : order.ordered) {
    if (joint->type != urdf::Joint::FIXED) last = joint->child_link_name;
  }
  return last;
}

std::string ChooseTcpLink(const urdf::ModelInterface& model, const JointOrder& order,
                          const std::vector<std::string>& link_order) {
  for (const std::string& name : link_order) {
    if (Lowercase(name) == "tcp" && model.getLink(name) != nullptr) return name;
  }
  if (model.getLink("tool0") != nullptr) return "tool0";
  if (model.getRoot() == nullptr) return "";

  std::map<std::string, std::string> body_of = {{model.getRoot()->name, ""}};  // link -> body
  for (const auto& joint : order.ordered) {
    const bool fixed = joint->type == urdf::Joint::FIXED;
    body_of[joint->child_link_name] =
        fixed ? body_of[joint->parent_link_name] : joint->child_link_name;
  }
  const std::string last_body = LastMovingLink(order);
  if (last_body.empty()) return "";
  for (const auto& joint : order.ordered) {
    const std::string& link = joint->child_link_name;
    const urdf::LinkConstSharedPtr child = model.getLink(link);
    if (joint->type == urdf::Joint::FIXED && body_of[link] == last_body && child != nullptr &&
        child->child_joints.empty()) {
      return link;
    }
  }
  return "";
}

}  // namespace mbstream::model_files
