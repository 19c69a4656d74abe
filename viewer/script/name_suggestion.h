// "did you mean ...?" suggestions by edit distance.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mbstream::scene_script {

// Levenshtein distance (insertions, deletions, substitutions), ASCII case-insensitive.
int EditDistance(std::string_view a, std::string_view b);

// The candidate closest to `name`, when it is close enough to be a likely typo: at most
// max(2, len/3) edits. Ties go to the first candidate.
std::optional<std::string> ClosestName(std::string_view name,
                                       const std::vector<std::string>& candidates);

// " (did you mean X?)" or "" when nothing is close.
std::string DidYouMean(std::string_view name, const std::vector<std::string>& candidates);

}  // namespace mbstream::scene_script
