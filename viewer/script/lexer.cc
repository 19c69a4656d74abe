#include "viewer/script/lexer.h"

#include <cctype>
#include <charconv>
#include <cmath>

namespace mbstream::scene_script {

namespace {

bool IsSpace(char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; }

bool IsDelimiter(char c) {
  return IsSpace(c) || c == '(' || c == ')' || c == ';' || c == ',' || c == '!' || c == '$';
}

// Tracks line and column while walking the text.
class Cursor {
 public:
  explicit Cursor(std::string_view text) : text_(text) {}
  bool done() const { return index_ >= text_.size(); }
  char peek() const { return text_[index_]; }
  size_t index() const { return index_; }
  SourcePosition position() const { return {line_, column_}; }
  void Advance() {
    if (text_[index_] == '\n') {
      ++line_;
      column_ = 1;
    } else {
      ++column_;
    }
    ++index_;
  }

 private:
  std::string_view text_;
  size_t index_ = 0;
  int line_ = 1;
  int column_ = 1;
};

}  // namespace

std::string Describe(const Token& token) {
  switch (token.kind) {
    case TokenKind::kWord:
      return "'" + token.text + "'";
    case TokenKind::kNumber:
      return "number " + token.text;
    case TokenKind::kEnd:
      return "the end of the script";
    default:
      return "'" + token.text + "'";
  }
}

bool ParseNumber(std::string_view text, double* value) {
  if (text.empty()) return false;
  size_t start = 0;
  if (text[0] == '+') start = 1;
  if (start >= text.size()) return false;
  const char first = text[start];
  const bool numeric_start = std::isdigit(static_cast<unsigned char>(first)) || first == '.' ||
                             (first == '-' && start + 1 < text.size());
  if (!numeric_start) return false;
  const char* begin = text.data() + start;
  const char* end = text.data() + text.size();
  double parsed = 0;
  const auto [ptr, ec] = std::from_chars(begin, end, parsed, std::chars_format::general);
  if (ec != std::errc() || ptr != end || !std::isfinite(parsed)) return false;
  *value = parsed;
  return true;
}

std::vector<Token> Tokenize(std::string_view text, Diagnostics* diagnostics) {
  std::vector<Token> tokens;
  Cursor cursor(text);
  while (!cursor.done()) {
    const char c = cursor.peek();
    if (IsSpace(c)) {
      cursor.Advance();
      continue;
    }
    if (c == '!') {
      while (!cursor.done() && cursor.peek() != '\n') cursor.Advance();
      continue;
    }
    if (c == '$') {
      const SourcePosition opened = cursor.position();
      cursor.Advance();
      while (!cursor.done() && cursor.peek() != '$') cursor.Advance();
      if (cursor.done()) {
        diagnostics->Error(opened,
                           "comment block opened with '$' is never closed; add a closing '$'");
      } else {
        cursor.Advance();
      }
      continue;
    }
    Token token;
    token.position = cursor.position();
    if (c == '(' || c == ')' || c == ';' || c == ',') {
      token.kind = c == '('   ? TokenKind::kLeftParen
                   : c == ')' ? TokenKind::kRightParen
                   : c == ';' ? TokenKind::kSemicolon
                              : TokenKind::kComma;
      token.text = std::string(1, c);
      cursor.Advance();
      tokens.push_back(std::move(token));
      continue;
    }
    const size_t begin = cursor.index();
    while (!cursor.done() && !IsDelimiter(cursor.peek())) cursor.Advance();
    token.text = std::string(text.substr(begin, cursor.index() - begin));
    token.kind = ParseNumber(token.text, &token.number) ? TokenKind::kNumber : TokenKind::kWord;
    tokens.push_back(std::move(token));
  }
  Token end;
  end.kind = TokenKind::kEnd;
  end.position = cursor.position();
  tokens.push_back(end);
  return tokens;
}

}  // namespace mbstream::scene_script
