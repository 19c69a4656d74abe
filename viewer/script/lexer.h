// Splits a scene script into tokens.
//
// White space separates terms. `(`, `)`, `;` and `,` are tokens of their own. A `!` starts
// a comment running to the end of its line; `$ ... $` is a comment block (it may span
// lines). Any other run of characters is a word, or a number when it reads completely as
// one (`486.5`, `-90.0`, `1e3`, `+2`). A word such as `x-150` is kept whole: the parser
// splits an axis letter glued to its number.
#pragma once

#include <string_view>
#include <vector>

#include "viewer/script/diagnostics.h"
#include "viewer/script/token.h"

namespace mbstream::scene_script {

// The tokens of `text`, ending with one kEnd token. Errors (an unclosed `$` block) go to
// `diagnostics`; lexing always completes.
std::vector<Token> Tokenize(std::string_view text, Diagnostics* diagnostics);

// `text` read as a whole number, or false (partial numbers, words, "inf", "nan" are not).
bool ParseNumber(std::string_view text, double* value);

}  // namespace mbstream::scene_script
