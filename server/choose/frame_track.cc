#include "server/choose/frame_track.h"

#include <algorithm>
#include <cmath>

namespace mbstream {

void FrameTrack::Append(const RunResult& result, int frame) {
  n = result.num_dofs;
  const auto k = static_cast<size_t>(frame);
  t.push_back(result.t[k]);
  q.insert(q.end(), result.q.begin() + static_cast<long>(k * n),
           result.q.begin() + static_cast<long>((k + 1) * n));
  tcp.insert(tcp.end(), result.tcp.begin() + static_cast<long>(k * 3),
             result.tcp.begin() + static_cast<long>((k + 1) * 3));
}

FrameTrack TrackOf(const RunResult& result) {
  FrameTrack track;
  track.n = result.num_dofs;
  for (int k = 0; k < result.num_frames(); ++k) track.Append(result, k);
  return track;
}

namespace {

double TcpDistance(const FrameTrack& a, const FrameTrack& b, int k) {
  double sum = 0.0;
  for (int c = 0; c < 3; ++c) {
    const double d = a.tcp[static_cast<size_t>(3 * k + c)] - b.tcp[static_cast<size_t>(3 * k + c)];
    sum += d * d;
  }
  return std::sqrt(sum);
}

double JointDistance(const FrameTrack& a, const FrameTrack& b, int k) {
  double largest = 0.0;
  for (int i = 0; i < a.n; ++i) {
    const auto index = static_cast<size_t>(k * a.n + i);
    largest = std::max(largest, std::abs(a.q[index] - b.q[index]));
  }
  return largest;
}

}  // namespace

TrackDifference CompareTracks(const FrameTrack& a, const FrameTrack& b) {
  TrackDifference difference;
  difference.frames = std::min(a.frames(), b.frames());
  if (difference.frames == 0 || a.n != b.n) return difference;
  for (int k = 0; k < difference.frames; ++k) {
    const double tcp = TcpDistance(a, b, k), joint = JointDistance(a, b, k);
    difference.tcp_m = std::max(difference.tcp_m, tcp);
    difference.joint_rad = std::max(difference.joint_rad, joint);
  }
  return difference;
}

double AgreementHorizon(const FrameTrack& a, const FrameTrack& b, double limit, bool tcp) {
  const int frames = std::min(a.frames(), b.frames());
  for (int k = 0; k < frames; ++k) {
    const double distance = tcp ? TcpDistance(a, b, k) : JointDistance(a, b, k);
    if (distance > limit) return k == 0 ? 0.0 : a.t[static_cast<size_t>(k - 1)];
  }
  return frames > 0 ? a.t[static_cast<size_t>(frames - 1)] : 0.0;
}

void TrackingSink::OnFrame(const RunResult& result, int frame) {
  track_.Append(result, frame);
  if (inner_ != nullptr) inner_->OnFrame(result, frame);
}

}  // namespace mbstream
