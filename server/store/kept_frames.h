// What an unfinished run left in the store, written into its row when the run is marked
// INTERRUPTED (a server restarted after a crash, or a dead replica's lease expired): the
// row then says how many frames survived and up to which time, as GetResult returns them.
// Both stores read the run's chunks (contiguous from chunk 0: Store::PutFrameChunk removes
// any numbered after the one it writes) and apply this.
#pragma once

#include <cstdint>
#include <string_view>

#include "mbstream/v1/run.pb.h"

namespace mbstream {

struct KeptFrames {
  int64_t frames = 0;          // stored frames, in every chunk
  double t_s = 0.0;            // simulated time of the last of them
  bool has_torques = false;    // the last frame carries drive efforts
  bool has_energy = false;     // a frame of the last chunk carries a non-zero energy
  int64_t dropped_chunks = 0;  // damaged chunks at the end, removed
};

// Reads the last stored chunk's blob (`last_chunk`) of a run whose chunks hold `frames`
// frames in all. False when the blob is corrupt or holds no frame.
bool ReadKeptFrames(int64_t frames, std::string_view last_chunk, KeptFrames& kept);

// An interrupted run's info says what survived: frames, t_s and stats.t_reached_s from
// `kept`, has_torques and has_energy when the frames carry them (the row of a run that was
// running has them unset: they are written when it ends), and its message names the frames
// kept (unchanged when there are none).
void ApplyKeptFrames(const KeptFrames& kept, v1::RunInfo& info);

}  // namespace mbstream
