#include "server/service/sent_frames.h"

#include <algorithm>
#include <cmath>
#include <functional>

namespace mbstream {

namespace {

bool Finite(const v1::Vector3& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z());
}

double MaxAbs(const v1::Vector3& p) {
  return std::max({std::abs(p.x()), std::abs(p.y()), std::abs(p.z())});
}

}  // namespace

int SentFrames::RunIndex(const std::string& run_id) {
  auto found = std::find(runs_.begin(), runs_.end(), run_id);
  if (found != runs_.end()) return static_cast<int>(found - runs_.begin());
  runs_.push_back(run_id);
  return static_cast<int>(runs_.size()) - 1;
}

void SentFrames::Record(const std::string& run_id, int64_t seq, double t_s,
                        Clock::time_point sent) {
  std::lock_guard<std::mutex> lock(mutex_);
  Entry& e = entries_[static_cast<size_t>(seq) % entries_.size()];
  e = Entry();
  e.run = RunIndex(run_id);
  e.seq = seq;
  e.t_s = t_s;
  e.sent = sent;
}

std::string SentFrames::Accept(v1::ProbeReport& report, Clock::time_point received) {
  if (report.probe().empty() || report.probe().size() > kMaxNameBytes) {
    return "its probe name is empty or longer than " + std::to_string(kMaxNameBytes) + " bytes";
  }
  if (report.frame().size() > kMaxNameBytes) {
    return "its frame name is longer than " + std::to_string(kMaxNameBytes) + " bytes";
  }
  if (!Finite(report.position_m()) || MaxAbs(report.position_m()) > kMaxCoordinateM) {
    return "its position is not finite or beyond 1e6 m";
  }
  if (report.seq() < 0) return "its seq is negative";
  std::lock_guard<std::mutex> lock(mutex_);
  Entry& e = entries_[static_cast<size_t>(report.seq()) % entries_.size()];
  if (e.seq != report.seq() || e.run < 0 ||
      (!report.run_id().empty() && runs_[e.run] != report.run_id())) {
    return "no frame " + std::to_string(report.seq()) +
           " of that run was sent on this stream (recently)";
  }
  const size_t name = std::hash<std::string>{}(report.probe());
  const auto end = e.probe_hash.begin() + e.probes;
  if (std::find(e.probe_hash.begin(), end, name) != end) {
    return "probe '" + report.probe() + "' was already reported for that frame";
  }
  if (e.probes == kMaxProbesPerFrame) {
    return "more than " + std::to_string(kMaxProbesPerFrame) + " probes for one frame";
  }
  e.probe_hash[e.probes++] = name;
  report.set_run_id(runs_[e.run]);
  report.set_t_s(e.t_s);
  report.set_latency_us(
      std::chrono::duration_cast<std::chrono::microseconds>(received - e.sent).count());
  return "";
}

}  // namespace mbstream
