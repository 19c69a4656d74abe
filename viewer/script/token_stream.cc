#include "viewer/script/token_stream.h"

#include <cctype>
#include <cmath>

#include "viewer/script/lexer.h"

namespace mbstream::scene_script {

const Token& TokenStream::Peek(size_t ahead) const {
  const size_t i = std::min(index_ + ahead, tokens_.size() - 1);
  return tokens_[i];
}

const Token& TokenStream::Next() {
  const Token& token = tokens_[index_];
  if (index_ + 1 < tokens_.size()) ++index_;
  return token;
}

bool TokenStream::PeekKeyword(std::string_view keyword, size_t ahead) const {
  const Token& token = Peek(ahead);
  return token.kind == TokenKind::kWord && EqualsIgnoreCase(token.text, keyword);
}

bool TokenStream::AcceptKeyword(std::string_view keyword) {
  if (!PeekKeyword(keyword)) return false;
  Next();
  return true;
}

bool TokenStream::Accept(TokenKind kind) {
  if (Peek().kind != kind) return false;
  Next();
  return true;
}

const Token& TokenStream::ExpectWord(std::string_view what) {
  if (Peek().kind != TokenKind::kWord && Peek().kind != TokenKind::kNumber) {
    FailExpected(Peek(), what);
  }
  return Next();
}

double TokenStream::ExpectNumber(std::string_view what) {
  if (Peek().kind != TokenKind::kNumber) FailExpected(Peek(), what);
  return Next().number;
}

int TokenStream::ExpectInteger(std::string_view what, int minimum, int maximum) {
  const Token& token = Peek();
  if (token.kind != TokenKind::kNumber) FailExpected(token, what);
  if (token.number != std::floor(token.number) || token.number < minimum ||
      token.number > maximum) {
    Fail(token, "expected " + std::string(what) + ", found " + Describe(token) +
                    "; give a whole number from " + std::to_string(minimum) + " to " +
                    std::to_string(maximum));
  }
  return static_cast<int>(Next().number);
}

double TokenStream::ExpectPositive(std::string_view what) {
  const Token& token = Peek();
  if (token.kind != TokenKind::kNumber) FailExpected(token, what);
  if (!(token.number > 0)) {
    Fail(token, "expected " + std::string(what) + ", found " + Describe(token) +
                    "; it must be greater than 0");
  }
  return Next().number;
}

void TokenStream::Expect(TokenKind kind, std::string_view what) {
  if (Peek().kind != kind) FailExpected(Peek(), what);
  Next();
}

void TokenStream::ExpectKeyword(std::string_view keyword, std::string_view context) {
  if (!PeekKeyword(keyword)) {
    FailExpected(Peek(), "'" + std::string(keyword) + "' " + std::string(context));
  }
  Next();
}

bool TokenStream::AcceptAxisValue(int* axis, double* value) {
  const Token& token = Peek();
  if (token.kind != TokenKind::kWord || token.text.empty()) return false;
  const char letter = static_cast<char>(std::tolower(static_cast<unsigned char>(token.text[0])));
  if (letter != 'x' && letter != 'y' && letter != 'z') return false;
  const int which = letter - 'x';
  if (token.text.size() == 1) {
    Next();
    *axis = which;
    *value = ExpectNumber(std::string("a number after '") + token.text + "'");
    return true;
  }
  double glued = 0;
  if (!ParseNumber(std::string_view(token.text).substr(1), &glued)) return false;
  Next();
  *axis = which;
  *value = glued;
  return true;
}

void TokenStream::FailExpected(const Token& at, std::string_view what, std::string_view advice) {
  std::string message = "expected " + std::string(what) + ", found " + Describe(at);
  if (!advice.empty()) message += "; " + std::string(advice);
  Fail(at, std::move(message));
}

void TokenStream::Fail(const Token& at, std::string message) {
  Error(at, std::move(message));
  throw CommandAbort{};
}

void TokenStream::Error(const Token& at, std::string message) {
  diagnostics_->Error(at.position, std::move(message));
}

void TokenStream::SkipCommand(int command_line,
                              const std::vector<std::string_view>& command_keywords) {
  while (!AtEnd()) {
    const Token& token = Peek();
    if (token.kind == TokenKind::kSemicolon) {
      Next();
      return;
    }
    // A command keyword at the start of a later line begins the next command.
    const bool starts_line = index_ == 0 || tokens_[index_ - 1].position.line < token.position.line;
    if (starts_line && token.position.line > command_line && token.kind == TokenKind::kWord) {
      for (std::string_view keyword : command_keywords) {
        if (EqualsIgnoreCase(token.text, keyword)) return;
      }
    }
    Next();
  }
}

}  // namespace mbstream::scene_script
