// Set, Render and Probe.
#include <algorithm>
#include <string>

#include "viewer/script/command_parsers.h"
#include "viewer/script/name_suggestion.h"

namespace mbstream::scene_script {

SetCommand ParseSet(TokenStream& in, const Token& keyword) {
  SetCommand set;
  set.position = keyword.position;
  const Token& name = in.ExpectWord("the assembly's name after 'Set'");
  set.name = name.text;
  set.name_position = name.position;
  in.ExpectKeyword("add", "and the components after the Set's name");
  while (!in.Accept(TokenKind::kSemicolon)) {
    if (in.AcceptKeyword("add")) continue;
    const Token& component = in.Peek();
    if (component.kind != TokenKind::kWord) {
      in.FailExpected(component, "a component name or ';' in Set '" + set.name + "'");
    }
    in.Next();
    Component c;
    c.name = component.text;
    c.position = component.position;
    if (auto placement = AcceptTransformClause(in)) c.placement = *placement;
    set.components.push_back(std::move(c));
  }
  if (set.components.empty()) {
    in.Error(name, "Set '" + set.name + "' adds no component; name at least one after 'add'");
  }
  return set;
}

RenderCommand ParseRender(TokenStream& in, const Token& keyword) {
  RenderCommand render;
  render.position = keyword.position;
  const Token& target = in.ExpectWord("the name of the component to render after 'Render'");
  render.target = target.text;
  render.target_position = target.position;
  const Token& word = in.Peek();
  if (!in.AcceptKeyword("color") && !in.AcceptKeyword("colour")) {
    const std::string hint =
        word.kind == TokenKind::kWord ? DidYouMean(word.text, {"color", "colour"}) : "";
    in.Fail(word, "expected 'color r g b' after the Render target, found " + Describe(word) + hint);
  }
  for (int i = 0; i < 3; ++i) {
    const Token& channel = in.Peek();
    render.color[i] = in.ExpectNumber("three colour channels r g b (0.0-1.0)");
    if (render.color[i] < 0 || render.color[i] > 1) {
      in.Error(channel, "colour channel " + channel.text + " is outside 0.0-1.0");
      render.color[i] = std::clamp(render.color[i], 0.0, 1.0);
    }
  }
  ExpectEndOfCommand(in, "the Render command");
  return render;
}

ProbeCommand ParseProbe(TokenStream& in, const Token& keyword) {
  ProbeCommand probe;
  probe.position = keyword.position;
  const Token& name = in.ExpectWord("the probe's name after 'Probe'");
  probe.name = name.text;
  probe.name_position = name.position;
  const Token& frame = in.ExpectWord(
      "the frame the probe is fixed in (the device, Device#k "
      "or World) after the probe's name");
  probe.frame_in = frame.text;
  probe.frame_in_position = frame.position;
  if (auto offset = AcceptTransformClause(in)) probe.offset = *offset;
  probe.refer_position = in.Peek().position;
  if (in.AcceptKeyword("refer")) {
    const Token& refer = in.ExpectWord(
        "the frame to report in (World, the device or "
        "Device#k) after 'Refer'");
    probe.refer = refer.text;
    probe.refer_position = refer.position;
  }
  ExpectEndOfCommand(in, "the Probe command");
  return probe;
}

}  // namespace mbstream::scene_script
