// SimulationService::GetResult: a stored result in chunks under the message size limit.
#include "server/service/simulation_service.h"
#include "server/service/status_from_exception.h"

namespace mbstream {

namespace {
constexpr size_t kChunkBytes = 1 << 20;  // about 1 MiB of frames or probes per message
}

grpc::Status SimulationService::GetResult(grpc::ServerContext* context,
                                          const v1::GetResultRequest* request,
                                          grpc::ServerWriter<v1::ResultChunk>* writer) {
  return Admit(*context, "GetResult", [&]() -> grpc::Status {
    RunManager::StoredResult result = runs_->Result(request->run_id());
    v1::ResultChunk chunk;
    *chunk.mutable_info() = result.info;
    if (!writer->Write(chunk)) return grpc::Status(grpc::StatusCode::CANCELLED, "client gone");
    chunk.Clear();
    size_t bytes = 0;
    auto flush = [&] {
      if (chunk.frames_size() == 0 && chunk.probes_size() == 0) return true;
      const bool ok = !context->IsCancelled() && writer->Write(chunk);
      chunk.Clear();
      bytes = 0;
      return ok;
    };
    for (v1::Frame& frame : result.frames) {
      bytes += frame.ByteSizeLong();
      *chunk.add_frames() = std::move(frame);
      if (bytes >= kChunkBytes && !flush()) {
        return grpc::Status(grpc::StatusCode::CANCELLED, "client gone");
      }
    }
    for (v1::ProbeReport& probe : result.probes) {
      bytes += probe.ByteSizeLong();
      *chunk.add_probes() = std::move(probe);
      if (bytes >= kChunkBytes && !flush()) {
        return grpc::Status(grpc::StatusCode::CANCELLED, "client gone");
      }
    }
    if (!flush()) return grpc::Status(grpc::StatusCode::CANCELLED, "client gone");
    return grpc::Status::OK;
  });
}

}  // namespace mbstream
