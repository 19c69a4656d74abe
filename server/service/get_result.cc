// SimulationService::GetResult and GetResults: a stored result in chunks under the message size
// limit, read from the store one frame chunk at a time (a long run is never in memory at once). The
// frames go out as stored, not parsed and serialized again (encoded_result_chunk.h). With
// `wait`, a run not yet ended is waited for (RunManager::AwaitChange) instead of refused.
#include <algorithm>
#include <chrono>

#include "server/runs/request_error.h"
#include "server/service/encoded_result_chunk.h"
#include "server/service/simulation_service.h"
#include "server/service/status_from_exception.h"
#include "server/wire/stats_conversion.h"

namespace mbstream {

namespace {
constexpr size_t kChunkBytes = 1 << 20;  // about 1 MiB of frames or probes per message
}

grpc::Status SimulationService::AwaitEnd(const grpc::ServerContext& context,
                                         const std::string& run_id, v1::RunInfo* ended) {
  // Woken by the run's changes; looks at the client and the server at least every second.
  constexpr auto kLook = std::chrono::seconds(1);
  v1::RunInfo& info = *ended;
  for (info = runs_->Get(run_id); !IsFinalState(info.state());) {
    if (context.IsCancelled()) return grpc::Status(grpc::StatusCode::CANCELLED, "client gone");
    if (stopping_) {
      return grpc::Status(grpc::StatusCode::UNAVAILABLE,
                          "the server is shutting down while run " + run_id + " was " +
                              v1::RunState_Name(info.state()) +
                              "; ask again (another replica, or this server once restarted)");
    }
    info = runs_->AwaitChange(run_id, info.state(), std::chrono::steady_clock::now() + kLook);
  }
  return grpc::Status::OK;
}

grpc::Status SimulationService::StillStored(const std::string& run_id) const {
  // A run deleted while it was read (run_deleter.h) may have lost its later chunks or probes
  // in between: the stream then ends NOT_FOUND, never OK with part of a result. Its row goes
  // in the transaction that deletes everything else: still stored now, everything read was.
  try {
    runs_->results().Info(run_id);
  } catch (const RequestError& error) {
    if (error.kind() != RequestErrorKind::kNotFound) throw;
    return grpc::Status(grpc::StatusCode::NOT_FOUND,
                        "run " + run_id +
                            " was deleted while its result was being sent; what was sent is "
                            "not all of it (`mbstream runs` lists the runs)");
  }
  return grpc::Status::OK;
}

grpc::Status SimulationService::SendResult(grpc::ServerContext& context, const std::string& run_id,
                                           const std::string& probe_set, bool wait,
                                           grpc::ServerWriter<v1::ResultChunk>& writer,
                                           size_t& sent_bytes) {
  // The info goes in the first message, with the first frames (a short result is one
  // message).
  EncodedResultChunk chunk;
  v1::RunInfo& info = *chunk.mutable_info();
  if (wait) {  // the final info as the wait read it (stored before it was shown)
    if (grpc::Status waited = AwaitEnd(context, run_id, &info); !waited.ok()) return waited;
  } else {
    info = runs_->results().Info(run_id);
  }
  // A replay's probe set is checked (NOT_FOUND) before anything is sent.
  std::vector<v1::ProbeReport> probes;
  if (!probe_set.empty()) probes = runs_->replays().ProbeSetReports(run_id, probe_set);
  const grpc::Status gone(grpc::StatusCode::CANCELLED, "client gone");
  auto flush = [&] {
    if (chunk.empty()) return true;
    const bool ok = !context.IsCancelled() && writer.Write(chunk.message());
    sent_bytes += chunk.bytes();
    chunk.Clear();
    return ok;
  };
  std::string data;  // one stored chunk at a time
  std::vector<std::string_view> frames;
  for (std::optional<int64_t> next = 0; next;) {
    frames.clear();
    next = runs_->results().Frames(run_id, *next, data, frames);
    for (std::string_view frame : frames) {
      chunk.AddFrame(frame);
      if (chunk.bytes() >= kChunkBytes && !flush()) return gone;
    }
  }
  std::string().swap(data);
  if (probe_set.empty()) probes = runs_->results().Probes(run_id);
  for (const v1::ProbeReport& probe : probes) {
    chunk.AddProbe(probe);
    if (chunk.bytes() >= kChunkBytes && !flush()) return gone;
  }
  if (grpc::Status stored = StillStored(run_id); !stored.ok()) return stored;
  if (!flush()) return gone;
  return grpc::Status::OK;
}

grpc::Status SimulationService::GetResult(grpc::ServerContext* context,
                                          const v1::GetResultRequest* request,
                                          grpc::ServerWriter<v1::ResultChunk>* writer) {
  size_t sent_bytes = 0;  // frames and probes, all messages
  const grpc::Status status = Admit(*context, "GetResult", [&]() -> grpc::Status {
    return SendResult(*context, request->run_id(), request->probe_set(), request->wait(), *writer,
                      sent_bytes);
  });
  // After the handler's messages and frames are freed, when they were a burst (a message
  // of 1 MiB or more; after every small result it cost more than the result).
  if (sent_bytes >= kChunkBytes) runs_->results().ReleaseMemory();
  return status;
}

grpc::Status SimulationService::GetResults(grpc::ServerContext* context,
                                           const v1::GetResultsRequest* request,
                                           grpc::ServerWriter<v1::ResultChunk>* writer) {
  size_t largest = 0;  // the largest result's frames and probes: a burst as in GetResult
  const grpc::Status status = Admit(*context, "GetResults", [&]() -> grpc::Status {
    if (request->run_ids().empty()) {
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                          "run_ids is empty; name at least one run");
    }
    for (const std::string& run_id : request->run_ids()) {
      size_t sent_bytes = 0;
      const grpc::Status sent =
          SendResult(*context, run_id, "", request->wait(), *writer, sent_bytes);
      largest = std::max(largest, sent_bytes);
      if (!sent.ok()) return sent;
    }
    return grpc::Status::OK;
  });
  // Not after every batch of small results (their sum passes 1 MiB every dozen or so).
  if (largest >= kChunkBytes) runs_->results().ReleaseMemory();
  return status;
}

}  // namespace mbstream
