// The parser's view of the tokens: look ahead, accept keywords (any case), expect what the
// grammar needs. A failed expectation records an error and throws CommandAbort, which the
// parser catches to skip to the next command.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "shared/common/ascii.h"
#include "viewer/script/diagnostics.h"
#include "viewer/script/token.h"

namespace mbstream::scene_script {

// Thrown after an error was recorded: the current command cannot be read further.
struct CommandAbort {};

using ::mbstream::EqualsIgnoreCase;  // shared/common/ascii.h

class TokenStream {
 public:
  TokenStream(const std::vector<Token>& tokens, Diagnostics* diagnostics)
      : tokens_(tokens), diagnostics_(diagnostics) {}

  const Token& Peek(size_t ahead = 0) const;
  const Token& Next();
  bool AtEnd() const { return Peek().kind == TokenKind::kEnd; }
  bool PeekIs(TokenKind kind) const { return Peek().kind == kind; }
  bool PeekKeyword(std::string_view keyword, size_t ahead = 0) const;
  bool AcceptKeyword(std::string_view keyword);
  bool Accept(TokenKind kind);

  // A word (a name). `what` completes "expected ...": "the cylinder's name".
  const Token& ExpectWord(std::string_view what);
  double ExpectNumber(std::string_view what);
  // A whole number from `minimum` to `maximum`.
  int ExpectInteger(std::string_view what, int minimum, int maximum = 1000000);
  // A number > 0.
  double ExpectPositive(std::string_view what);
  void Expect(TokenKind kind, std::string_view what);
  void ExpectKeyword(std::string_view keyword, std::string_view context);

  // An axis letter with its number, written `x 150` or glued `x150`, `x-150`. False (and
  // nothing consumed) when the next token is no axis letter.
  bool AcceptAxisValue(int* axis, double* value);

  // Records "expected WHAT, found TOKEN[; advice]" at `at` and throws CommandAbort.
  [[noreturn]] void FailExpected(const Token& at, std::string_view what,
                                 std::string_view advice = {});
  [[noreturn]] void Fail(const Token& at, std::string message);
  void Error(const Token& at, std::string message);

  // Recovery: skips past the next ';', or up to a command keyword that starts a line after
  // `command_line` (the line where the failed command began).
  void SkipCommand(int command_line, const std::vector<std::string_view>& command_keywords);

 private:
  const std::vector<Token>& tokens_;
  Diagnostics* diagnostics_;
  size_t index_ = 0;
};

}  // namespace mbstream::scene_script
