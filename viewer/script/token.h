// The lexer's output: words, numbers and punctuation, each with its position.
#pragma once

#include <string>

#include "viewer/script/source_position.h"

namespace mbstream::scene_script {

enum class TokenKind { kWord, kNumber, kLeftParen, kRightParen, kSemicolon, kComma, kEnd };

struct Token {
  TokenKind kind = TokenKind::kEnd;
  std::string text;   // as written
  double number = 0;  // kNumber only
  SourcePosition position;
};

// How a token is named in messages: "'Cube'", "number 12", "';'", "the end of the script".
std::string Describe(const Token& token);

}  // namespace mbstream::scene_script
