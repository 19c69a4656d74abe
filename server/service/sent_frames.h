// The frames one Subscribe stream has sent, to check and time the probe reports it gets back.
//
// A viewer's probe report is accepted only for a frame this stream sent (run and seq), at
// most once per probe name and at most kMaxProbesPerFrame probes per frame, with a bounded
// probe and frame name and finite coordinates. The run id, the simulated time and the
// round-trip latency come from what the server sent, never from the client. Thread-safe:
// the stream's writer records, its reader checks.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "mbstream/v1/frame.pb.h"

namespace mbstream {

class SentFrames {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr int kRemembered = 8192;        // the last frames sent, for late reports
  static constexpr int kMaxProbesPerFrame = 16;   // distinct probe names per frame
  static constexpr size_t kMaxNameBytes = 128;    // probe and frame names
  static constexpr double kMaxCoordinateM = 1e6;  // |x|, |y|, |z| of a probe position, m

  // Frame `seq` at simulated time `t_s` of run `run_id` went out at `sent`.
  void Record(const std::string& run_id, int64_t seq, double t_s, Clock::time_point sent);

  // Checks `report` (received at `received`) against the frames sent. On success fills its
  // run_id, t_s and latency_us from the record and returns ""; otherwise returns why it is
  // refused and leaves the report unchanged.
  std::string Accept(v1::ProbeReport& report, Clock::time_point received);

 private:
  struct Entry {
    int run = -1;  // index into runs_
    int64_t seq = -1;
    double t_s = 0.0;
    Clock::time_point sent;
    int probes = 0;                                       // reports accepted
    std::array<size_t, kMaxProbesPerFrame> probe_hash{};  // their names' hashes
  };
  int RunIndex(const std::string& run_id);  // mutex_ held

  std::mutex mutex_;
  std::vector<std::string> runs_;  // runs this stream has sent frames of
  std::array<Entry, kRemembered> entries_{};
};

}  // namespace mbstream
