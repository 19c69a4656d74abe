#include "server/store/kept_frames.h"

#include <cstdio>
#include <string>
#include <vector>

#include "server/store/frame_chunks.h"

namespace mbstream {

bool ReadKeptFrames(int64_t frames, std::string_view last_chunk, KeptFrames& kept) {
  std::vector<v1::Frame> decoded;
  if (!DecodeFrameChunk(last_chunk, decoded) || decoded.empty()) return false;
  kept.frames = frames;
  kept.t_s = decoded.back().t_s();
  kept.has_torques = decoded.back().tau_size() > 0;
  kept.has_energy = false;
  for (const v1::Frame& frame : decoded) {
    if (frame.kinetic_j() != 0.0 || frame.potential_j() != 0.0) kept.has_energy = true;
  }
  return true;
}

void ApplyKeptFrames(const KeptFrames& kept, v1::RunInfo& info) {
  info.set_frames(kept.frames);
  info.set_t_s(kept.t_s);
  info.mutable_stats()->set_t_reached_s(kept.t_s);
  if (kept.frames == 0) return;
  if (kept.has_torques) info.set_has_torques(true);
  if (kept.has_energy) info.set_has_energy(true);
  char t[32];
  std::snprintf(t, sizeof t, "%.6g", kept.t_s);
  std::string note = "; the " + std::to_string(kept.frames) + " frames stored up to t = " + t +
                     " s are kept (mbstream result)";
  if (kept.dropped_chunks > 0) {
    note += "; " + std::to_string(kept.dropped_chunks) +
            " later chunks of frames were damaged (the machine stopped before they reached the "
            "disk) and were removed";
  }
  info.set_message(info.message() + note);
}

}  // namespace mbstream
