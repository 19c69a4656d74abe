// A run's output frames as the accuracy checks compare them: times, joint positions and TCP.
// A FrameSink that keeps this copy while passing every frame on lets a streamed run (whose
// RunResult keeps only its latest frame) be checked after it ends.
#pragma once

#include <vector>

#include "server/sim/run_result.h"

namespace mbstream {

struct FrameTrack {
  int n = 0;                // joints
  std::vector<double> t;    // s
  std::vector<double> q;    // rad or m, n per frame
  std::vector<double> tcp;  // m, 3 per frame

  int frames() const { return static_cast<int>(t.size()); }
  void Append(const RunResult& result, int frame);
};

// Every frame of a RunResult that holds them all (no sink that keeps frames).
FrameTrack TrackOf(const RunResult& result);

// How far two tracks of the same output times are apart, over their common frames.
struct TrackDifference {
  double tcp_m = 0.0;      // m, largest TCP distance
  double joint_rad = 0.0;  // rad or m, largest joint difference
  int frames = 0;          // frames compared
};

TrackDifference CompareTracks(const FrameTrack& a, const FrameTrack& b);

// The last time up to which the tracks' TCPs (tcp = true) or joints stay within `limit`:
// the first frame beyond it, less one frame; 0 when frame 0 is already beyond it.
double AgreementHorizon(const FrameTrack& a, const FrameTrack& b, double limit, bool tcp);

// Passes each frame to `inner` (if any) and keeps a FrameTrack of it.
class TrackingSink : public FrameSink {
 public:
  explicit TrackingSink(FrameSink* inner) : inner_(inner) {}
  void OnFrame(const RunResult& result, int frame) override;
  bool KeepsFrames() const override { return inner_ != nullptr && inner_->KeepsFrames(); }
  const FrameTrack& track() const { return track_; }

 private:
  FrameSink* inner_;
  FrameTrack track_;
};

}  // namespace mbstream
