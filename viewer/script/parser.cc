#include "viewer/script/parser.h"

#include <string>

#include "viewer/script/command_parsers.h"
#include "viewer/script/lexer.h"
#include "viewer/script/name_suggestion.h"

namespace mbstream::scene_script {

namespace {

using ParseFunction = Command (*)(TokenStream&, const Token&);

struct Entry {
  std::string_view keyword;
  ParseFunction parse;
};

template <auto F>
Command Wrap(TokenStream& in, const Token& keyword) {
  return F(in, keyword);
}

const std::vector<Entry>& Entries() {
  static const std::vector<Entry> entries = {
      {"Device", Wrap<ParseDevice>}, {"Cylinder", Wrap<ParseCylinder>},
      {"Cone", Wrap<ParseCone>},     {"Cube", Wrap<ParseCube>},
      {"Sphere", Wrap<ParseSphere>}, {"Polyprism", Wrap<ParsePolyprism>},
      {"Module", Wrap<ParseModule>}, {"Part", Wrap<ParseStlPart>},
      {"Set", Wrap<ParseSet>},       {"Render", Wrap<ParseRender>},
      {"Probe", Wrap<ParseProbe>},
  };
  return entries;
}

}  // namespace

const std::vector<std::string_view>& CommandKeywords() {
  static const std::vector<std::string_view> keywords = [] {
    std::vector<std::string_view> k;
    for (const Entry& e : Entries()) k.push_back(e.keyword);
    return k;
  }();
  return keywords;
}

std::vector<Command> ParseScript(std::string_view text, Diagnostics* diagnostics) {
  const std::vector<Token> tokens = Tokenize(text, diagnostics);
  TokenStream in(tokens, diagnostics);
  std::vector<Command> commands;
  while (!in.AtEnd()) {
    if (in.Accept(TokenKind::kSemicolon)) continue;  // an empty command
    const Token& keyword = in.Next();
    try {
      const Entry* entry = nullptr;
      if (keyword.kind == TokenKind::kWord) {
        for (const Entry& e : Entries()) {
          if (EqualsIgnoreCase(keyword.text, e.keyword)) entry = &e;
        }
      }
      if (!entry) {
        std::vector<std::string> names(CommandKeywords().begin(), CommandKeywords().end());
        const std::string hint =
            keyword.kind == TokenKind::kWord ? DidYouMean(keyword.text, names) : "";
        in.Fail(keyword,
                "expected a command (Device, Cylinder, Cone, Cube, Sphere, Polyprism, "
                "Module, Part, Set, Render or Probe), found " +
                    Describe(keyword) + hint);
      }
      commands.push_back(entry->parse(in, keyword));
    } catch (const CommandAbort&) {
      in.SkipCommand(keyword.position.line, CommandKeywords());
    }
  }
  return commands;
}

}  // namespace mbstream::scene_script
