// SimulationService::ExportMcap: a stored, ended run as one MCAP file written here
// (server/mcap/stored_run_mcap.h) as the run is read from the store one frame chunk at a time,
// its bytes streamed to the client as they are written. Memory: a stored chunk, an MCAP chunk
// and a message, never the run.
#include <memory>

#include "server/mcap/stored_run_mcap.h"
#include "server/service/simulation_service.h"

namespace mbstream {

namespace {

constexpr size_t kMessageBytes = 1 << 20;  // the file's bytes per message, at most

struct ClientGone {};

// The file's bytes into the call's stream, in messages of at most kMessageBytes; the first
// message carries the run's info. Throws ClientGone when the client has gone.
class StreamSink : public mcap::McapSink {
 public:
  StreamSink(grpc::ServerContext& context, grpc::ServerWriter<v1::McapFileChunk>& writer,
             const v1::RunInfo& info, size_t& sent_bytes)
      : context_(context), writer_(writer), sent_bytes_(sent_bytes) {
    *message_.mutable_info() = info;
  }

  void Write(std::string_view bytes) override {
    pending_.append(bytes);
    while (pending_.size() >= kMessageBytes) Send(kMessageBytes);
  }
  void Close() override { Send(pending_.size()); }

 private:
  void Send(size_t count) {
    message_.set_data(pending_.data(), count);
    if (context_.IsCancelled() || !writer_.Write(message_)) throw ClientGone{};
    sent_bytes_ += count;
    pending_.erase(0, count);
    message_.Clear();
  }

  grpc::ServerContext& context_;
  grpc::ServerWriter<v1::McapFileChunk>& writer_;
  size_t& sent_bytes_;
  v1::McapFileChunk message_;
  std::string pending_;
};

}  // namespace

grpc::Status SimulationService::SendMcap(grpc::ServerContext& context,
                                         const v1::ExportMcapRequest& request,
                                         grpc::ServerWriter<v1::McapFileChunk>& writer,
                                         size_t& sent_bytes) {
  const std::string& run_id = request.run_id();
  v1::RunInfo info;
  if (request.wait()) {
    if (grpc::Status waited = AwaitEnd(context, run_id, &info); !waited.ok()) return waited;
  } else {
    info = runs_->results().Info(run_id);
  }
  // Everything that can be refused is checked before the first byte is sent.
  const mcap::RunMcapOptions options =
      mcap::StoredRunMcapOptions(info, request.compression(), request.start(), "");
  std::vector<v1::ProbeReport> probes;
  if (!request.probe_set().empty())
    probes = runs_->replays().ProbeSetReports(run_id, request.probe_set());
  const std::shared_ptr<const CompiledModel> model = models_->Find(info.model_id());
  const std::string model_text = models_->Bundle(info.model_id()).urdf();

  try {
    mcap::StoredRunMcapWriter mcap(std::make_unique<StreamSink>(context, writer, info, sent_bytes),
                                   info, model->model, model_text, options);
    std::string data;  // one stored chunk at a time
    std::vector<std::string_view> frames;
    for (std::optional<int64_t> next = 0; next;) {
      frames.clear();
      next = runs_->results().Frames(run_id, *next, data, frames);
      mcap.AddFrames(frames);
    }
    std::string().swap(data);
    if (request.probe_set().empty()) probes = runs_->results().Probes(run_id);
    if (grpc::Status stored = StillStored(run_id); !stored.ok()) return stored;
    mcap.Finish(probes);
  } catch (const ClientGone&) {
    return grpc::Status(grpc::StatusCode::CANCELLED, "client gone");
  }
  return grpc::Status::OK;
}

grpc::Status SimulationService::ExportMcap(grpc::ServerContext* context,
                                           const v1::ExportMcapRequest* request,
                                           grpc::ServerWriter<v1::McapFileChunk>* writer) {
  size_t sent_bytes = 0;
  const grpc::Status status = Admit(*context, "ExportMcap", [&]() -> grpc::Status {
    return SendMcap(*context, *request, *writer, sent_bytes);
  });
  if (sent_bytes >= kMessageBytes) runs_->results().ReleaseMemory();  // as GetResult after a burst
  return status;
}

}  // namespace mbstream
