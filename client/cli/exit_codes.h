// The exit codes of `mbstream` (README.md, docs/budgets.md).
#pragma once

#include <string>
#include <string_view>

namespace mbstream::cli {

inline constexpr int kExitOk = 0;         // done; a run finished with trust ok
inline constexpr int kExitRunFailed = 1;  // the run did not finish (its state says why)
inline constexpr int kExitBadRequest = 2;
inline constexpr int kExitUnreachable = 3;  // the server is unreachable (or internal error)
// The run finished but its own error indicators say the result cannot be trusted
// (trust: low), or it missed its accuracy target; --accept-untrusted turns this into 0.
inline constexpr int kExitUntrusted = 4;

// The line about a run that had an accuracy target and was verified: "target: met" or
// "target: missed (MESSAGE)", MESSAGE naming the achieved error and what to change; empty
// when there was no target or no check. A missed target exits kExitUntrusted, as low trust.
inline std::string TargetLine(bool met, const std::string& message) {
  if (met) return "target: met";
  constexpr std::string_view kSaid = "target missed: ";  // the check's message says it again
  const std::string_view text = std::string_view(message).starts_with(kSaid)
                                    ? std::string_view(message).substr(kSaid.size())
                                    : std::string_view(message);
  return "target: missed (" + (text.empty() ? std::string("see stats.json") : std::string(text)) +
         ")";
}

// The CLI's last line about a finished run: "trust: ok" or "trust: low (REASON)";
// "trust: n/a" when the run did not finish.
inline std::string TrustLine(const std::string& trust, const std::string& reason) {
  if (trust.empty()) return "trust: n/a";
  if (trust == "low") return "trust: low (" + reason + ")";
  return "trust: " + trust;
}

}  // namespace mbstream::cli
