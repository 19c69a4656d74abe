#include "server/app/server_metrics.h"

#include <algorithm>
#include <cctype>
#include <chrono>

namespace mbstream {

namespace {

constexpr const char* kStoreOperationNames[] = {"put_model",
                                                "list_models",
                                                "get_model_bundle",
                                                "model_bytes",
                                                "put_run",
                                                "get_run",
                                                "list_runs",
                                                "put_frame_chunk",
                                                "finish_run",
                                                "get_frame_chunk",
                                                "add_probes",
                                                "get_probes",
                                                "frame_chunk_holding",
                                                "create_probe_set",
                                                "add_probe_set_reports",
                                                "list_probe_sets",
                                                "get_probe_set",
                                                "get_probe_set_reports",
                                                "mark_unfinished_runs_interrupted",
                                                "claim_queued_run",
                                                "renew_lease",
                                                "reap_expired_leases",
                                                "put_run_if_held",
                                                "end_queued_run",
                                                "list_running_runs",
                                                "delete_run",
                                                "delete_model",
                                                "set_run_keep",
                                                "list_sweep_runs",
                                                "mark_sweep_cancelled",
                                                "sweep_cancelled",
                                                "add_sweep",
                                                "get_sweep",
                                                "list_open_sweeps",
                                                "add_sweep_runs",
                                                "count_sweep_runs",
                                                "list_unfinished_sweep_runs"};
static_assert(std::size(kStoreOperationNames) == static_cast<size_t>(StoreOperation::kCount));

bool IsFinal(v1::RunState state) { return state >= v1::FINISHED && state <= v1::INTERRUPTED; }

std::string Lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

std::string CompilerName() {
#if defined(__clang__)
  return "clang " __clang_version__;
#elif defined(__GNUC__)
  return "gcc " __VERSION__;
#else
  return "unknown";
#endif
}

}  // namespace

ServerMetrics::ServerMetrics(metrics::Registry& registry) : registry_(registry) {
  metrics::Family<metrics::Gauge>& runs = registry.Gauges(
      "mbstream_runs", "Runs of this replica by state (queued, running)", {"state"});
  queued_ = &runs.With({"queued"});
  running_ = &runs.With({"running"});
  metrics::Family<metrics::Counter>& ended = registry.Counters(
      "mbstream_runs_ended_total", "Runs of this replica that ended, by final state", {"state"});
  for (int state = v1::FINISHED; state <= v1::INTERRUPTED; ++state) {
    ended_[state] = &ended.With({Lowercase(v1::RunState_Name(static_cast<v1::RunState>(state)))});
  }
  frames_ = &registry
                 .Counters("mbstream_frames_total",
                           "Frames of the runs this replica integrated, counted as they are "
                           "stored (chunk by chunk)")
                 .With({});
  probe_latency_ = &registry
                        .Histograms("mbstream_probe_latency_seconds",
                                    "Round trip from a frame's send to its viewer's probe "
                                    "report, as stored with the run",
                                    metrics::ExponentialBuckets(100e-6, 2.0, 15))
                        .With({});
  metrics::Family<metrics::Histogram>& store = registry.Histograms(
      "mbstream_store_operation_duration_seconds", "Time of one store operation, by operation",
      metrics::ExponentialBuckets(100e-6, 4.0, 9), {"operation"});
  for (size_t i = 0; i < store_.size(); ++i) store_[i] = &store.With({kStoreOperationNames[i]});
  registry.Gauges("mbstream_build_info", "Build of this server (value 1)", {"version", "compiler"})
      .With({MBSTREAM_VERSION, CompilerName()})
      .Set(1);
  registry.Gauges("process_start_time_seconds", "Start of this process, s since the Unix epoch")
      .With({})
      .Set(std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch())
               .count());
}

metrics::Gauge& ServerMetrics::runs(v1::RunState state) {
  return state == v1::RUNNING ? *running_ : *queued_;
}

metrics::Counter& ServerMetrics::runs_ended(v1::RunState state) {
  return *ended_[IsFinal(state) ? state : v1::FAILED];
}

void ServerMetrics::SetSubscriberCount(std::function<double()> read) {
  registry_.GaugeFunction("mbstream_subscribers", "Open Subscribe and WatchRun streams",
                          std::move(read));
}

}  // namespace mbstream
