// "did you mean" for a mistyped name: the closest of the known names by edit distance, when
// it is close enough to be the one meant (at most a third of the word's letters apart).
#pragma once

#include <algorithm>
#include <string>
#include <vector>

namespace mbstream {

// Levenshtein distance, case-insensitive.
inline int EditDistance(const std::string& a, const std::string& b) {
  const auto lower = [](char c) { return static_cast<char>(c >= 'A' && c <= 'Z' ? c + 32 : c); };
  std::vector<int> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = static_cast<int>(j);
  for (size_t i = 1; i <= a.size(); ++i) {
    int diagonal = row[0];
    row[0] = static_cast<int>(i);
    for (size_t j = 1; j <= b.size(); ++j) {
      const int up = row[j];
      row[j] = std::min(
          {row[j] + 1, row[j - 1] + 1, diagonal + (lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// The known name closest to `word`, or "" when none is close (or `word` is one of them).
inline std::string ClosestName(const std::string& word, const std::vector<std::string>& known) {
  std::string best;
  int best_distance = std::max<int>(2, static_cast<int>(word.size()) / 3) + 1;
  for (const std::string& name : known) {
    const int distance = EditDistance(word, name);
    if (distance == 0) return "";
    if (distance < best_distance) {
      best_distance = distance;
      best = name;
    }
  }
  return best;
}

// "; did you mean 'NAME'?" for the closest known name, or "".
inline std::string DidYouMean(const std::string& word, const std::vector<std::string>& known) {
  const std::string closest = ClosestName(word, known);
  return closest.empty() ? "" : "; did you mean '" + closest + "'?";
}

}  // namespace mbstream
