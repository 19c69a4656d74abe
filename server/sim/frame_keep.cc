#include "server/sim/frame_keep.h"

#include <charconv>

namespace mbstream {

long KeptFrameCount(const FrameKeep& keep, long computed) {
  if (computed <= 0) return 0;
  switch (keep.mode) {
    case FrameKeep::Mode::kAll:
      return computed;
    case FrameKeep::Mode::kEvery:  // 0, N, 2N, ... and the last
      return (computed - 1) / keep.every + 1 + ((computed - 1) % keep.every != 0 ? 1 : 0);
    case FrameKeep::Mode::kFinal:
      return 1;
    case FrameKeep::Mode::kSummary:
      return 0;
  }
  return computed;
}

std::string FrameKeepName(const FrameKeep& keep) {
  switch (keep.mode) {
    case FrameKeep::Mode::kAll:
      return "all";
    case FrameKeep::Mode::kEvery:
      return "every:" + std::to_string(keep.every);
    case FrameKeep::Mode::kFinal:
      return "final";
    case FrameKeep::Mode::kSummary:
      return "summary";
  }
  return "all";
}

bool ParseFrameKeep(std::string_view text, FrameKeep* keep, std::string* why) {
  constexpr std::string_view kEvery = "every:";
  constexpr long kMostEvery = 1'000'000'000;
  if (text.empty() || text == "all") {
    *keep = FrameKeep{};
    return true;
  }
  if (text == "final") {
    *keep = FrameKeep{FrameKeep::Mode::kFinal};
    return true;
  }
  if (text == "summary") {
    *keep = FrameKeep{FrameKeep::Mode::kSummary};
    return true;
  }
  if (text.substr(0, kEvery.size()) == kEvery) {
    const std::string_view digits = text.substr(kEvery.size());
    long n = 0;
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), n);
    if (error == std::errc() && end == digits.data() + digits.size() && n >= 1 && n <= kMostEvery) {
      *keep = n == 1 ? FrameKeep{} : FrameKeep{FrameKeep::Mode::kEvery, n};
      return true;
    }
    *why = "every:N needs a whole N from 1 to " + std::to_string(kMostEvery) +
           " (every:10 keeps "
           "frames 0, 10, 20, ... and the last)";
    return false;
  }
  *why =
      "give all (every frame, the default), every:N (every Nth frame and the last), final "
      "(the last frame) or summary (no frame: the run's summary only)";
  return false;
}

}  // namespace mbstream
