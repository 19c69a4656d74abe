// Device Title (Shift ... Euler ... LBox blen) Joint ... Tcp (...) Extend k Initial (...);
#include <string>

#include "viewer/script/command_parsers.h"
#include "viewer/script/name_suggestion.h"

namespace mbstream::scene_script {

namespace {

JointDeclaration ParseJoint(TokenStream& in, const Token& keyword, int expected_number,
                            int parent) {
  JointDeclaration joint;
  joint.position = keyword.position;
  joint.parent = parent;
  const Token& number_token = in.Peek();
  joint.number = in.ExpectInteger("the joint number after 'Joint'", 1);
  if (joint.number != expected_number) {
    in.Error(number_token, "expected Joint " + std::to_string(expected_number) + ", found Joint " +
                               std::to_string(joint.number) +
                               "; joints are numbered 1, 2, 3 ... in order");
    joint.number = expected_number;
  }
  if (auto pre = AcceptTransformClause(in)) joint.pre = *pre;
  const Token& type = in.Peek();
  if (in.AcceptKeyword("revolute")) {
    joint.type = JointType::kRevolute;
  } else if (in.AcceptKeyword("prismatic")) {
    joint.type = JointType::kPrismatic;
  } else {
    const std::string hint =
        type.kind == TokenKind::kWord ? DidYouMean(type.text, {"Revolute", "Prismatic"}) : "";
    in.Fail(type, "expected Revolute or Prismatic for joint " + std::to_string(joint.number) +
                      ", found " + Describe(type) + hint);
  }
  const Token& axis = in.Peek();
  if (in.AcceptKeyword("x")) {
    joint.axis = 0;
  } else if (in.AcceptKeyword("y")) {
    joint.axis = 1;
  } else if (in.AcceptKeyword("z")) {
    joint.axis = 2;
  } else {
    in.FailExpected(axis, "the joint axis x, y or z after '" + type.text + "'");
  }
  if (auto post = AcceptTransformClause(in)) joint.post = *post;
  return joint;
}

std::vector<double> ParseInitial(TokenStream& in) {
  in.Expect(TokenKind::kLeftParen, "'(' and the initial joint values after 'Initial'");
  std::vector<double> values;
  while (!in.Accept(TokenKind::kRightParen)) {
    if (in.Accept(TokenKind::kComma)) continue;
    values.push_back(in.ExpectNumber("a joint value (degrees or mm) or ')' in Initial"));
  }
  return values;
}

}  // namespace

DeviceCommand ParseDevice(TokenStream& in, const Token& keyword) {
  DeviceCommand device;
  device.position = keyword.position;
  const Token& name = in.ExpectWord("the device's name after 'Device'");
  device.name = name.text;
  device.name_position = name.position;
  if (device.name.find('#') != std::string::npos) {
    in.Error(name, "a device name cannot contain '#' ('" + device.name +
                       "#k' names its link k); choose a name without it");
  }
  if (auto placement = AcceptTransformClause(in, &device.lbox_mm)) device.placement = *placement;
  int parent = 0;
  while (!in.Accept(TokenKind::kSemicolon)) {
    const Token& token = in.Peek();
    if (in.AcceptKeyword("joint")) {
      const int number = static_cast<int>(device.joints.size()) + 1;
      device.joints.push_back(ParseJoint(in, token, number, parent));
      parent = number;
    } else if (in.AcceptKeyword("tcp")) {
      if (device.tcp) in.Error(token, "Tcp is given twice in the Device; keep one");
      device.tcp_position = token.position;
      device.tcp_frame = static_cast<int>(device.joints.size());
      auto clause = AcceptTransformClause(in);
      if (!clause) in.FailExpected(in.Peek(), "'(shift ...)' placing the TCP after 'Tcp'");
      device.tcp = *clause;
    } else if (in.AcceptKeyword("extend")) {
      const Token& frame = in.Peek();
      const int k = in.ExpectInteger("the frame number to branch from after 'Extend'", 0);
      const int defined = static_cast<int>(device.joints.size());
      if (k > defined) {
        in.Error(frame, "Extend " + std::to_string(k) + ": only frames 0.." +
                            std::to_string(defined) +
                            " exist here; branch from the base (0) or a joint defined above");
      } else {
        parent = k;
      }
      device.extends.push_back({token.position, k});
    } else if (in.AcceptKeyword("initial")) {
      if (device.initial) in.Error(token, "Initial is given twice in the Device; keep one");
      device.initial_position = token.position;
      device.initial = ParseInitial(in);
    } else {
      const std::string hint = token.kind == TokenKind::kWord
                                   ? DidYouMean(token.text, {"Joint", "Tcp", "Extend", "Initial"})
                                   : "";
      in.Fail(token, "expected Joint, Tcp, Extend, Initial or ';' in the Device command, found " +
                         Describe(token) + hint);
    }
  }
  if (device.initial && device.initial->size() != device.joints.size()) {
    Token at;
    at.position = device.initial_position;
    in.Error(at, "Initial gives " + std::to_string(device.initial->size()) +
                     " values but the device has " + std::to_string(device.joints.size()) +
                     " joints; give one value per joint (degrees or mm)");
  }
  return device;
}

}  // namespace mbstream::scene_script
