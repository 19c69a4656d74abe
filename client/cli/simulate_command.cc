#include "client/cli/simulate_command.h"

#include <spdlog/spdlog.h>

#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "client/cli/exit_codes.h"
#include "client/cli/model_flags.h"
#include "client/cli/run_overrides.h"
#include "client/cli/summary_line.h"
#include "server/engine/engine.h"
#include "server/mcap/run_mcap.h"
#include "server/model/coordinate_names.h"
#include "server/parse/model_file.h"
#include "server/results/results_stream.h"
#include "server/sim/input_sanity.h"
#include "server/sim/loop_run.h"
#include "server/sim/run_size.h"
#include "server/sim/run_validation.h"
#include "server/spec/run_spec_json.h"
#include "server/wire/model_info.h"
#include "server/wire/stats_conversion.h"
#include "shared/common/check.h"

namespace mbstream::cli {

namespace {

struct SimulateOptions {
  std::string model_path;
  std::string spec_path;
  std::string out_dir;
  RunOverrides overrides;
  std::string mcap_path;  // also write the run as MCAP (server/mcap/run_mcap.h)
  std::string mcap_compression = "zstd";
  std::string mcap_start;  // the time of t = 0 (default: now, UTC)
  bool accept_untrusted = false;
  bool repair = false;
  bool couple_mimic = false;
  bool floating_base = false;
  std::vector<std::string> package_paths;
  // The server's limits and defaults (mbstream-server's flags of the same names), so that
  // simulate and the server agree on every input.
  int max_links = 256;
  RunSizeLimits size;
};

// Fields of a RunSpec that only the server acts on: said once, not silently dropped.
void WarnServerOnlyFields(const v1::RunSpec& spec) {
  if (spec.realtime() != 0.0) {
    std::cerr << "mbstream simulate: warning: spec.realtime is ignored: simulate runs as fast "
                 "as it can (pacing is for the server's live runs)\n";
  }
  if (spec.retries() != 0) {
    std::cerr << "mbstream simulate: warning: spec.retries is ignored: simulate runs once "
                 "(retries are for the server's interrupted runs)\n";
  }
}

// Hands each frame to every sink (the CSV files and the MCAP file); each keeps its own frames.
class FrameSinks : public FrameSink {
 public:
  void Add(FrameSink* sink) { sinks_.push_back(sink); }
  void OnFrame(const RunResult& result, int frame) override {
    for (FrameSink* sink : sinks_) sink->OnFrame(result, frame);
  }
  bool KeepsFrames() const override { return true; }

 private:
  std::vector<FrameSink*> sinks_;
};

std::string ReadModelText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The run's summary line on stdout (the same line as `mbstream run --watch`: summary_line.h).
void PrintSummary(const RunStats& s, int64_t frames, const std::string& out_dir) {
  std::cout << SummaryLine(RunStatusName(s.status), frames, StatsToProto(s)) << "\nresults in "
            << out_dir << "\n";
}

// Messages on a failed or missed run, the trust line, and the exit code.
int ExitCodeOf(const RunStats& s, bool accept_untrusted) {
  if (s.status != RunStatus::kFinished) {
    std::cerr << "mbstream simulate: run " << RunStatusName(s.status) << ": " << s.message << "\n";
  }
  const bool missed =
      s.status == RunStatus::kFinished && s.target_met.has_value() && !*s.target_met;
  if (s.status == RunStatus::kFinished && s.target_met.has_value()) {
    std::cout << TargetLine(*s.target_met, s.message) << "\n";
  }
  std::cout << TrustLine(TrustName(s.trust), s.trust_reason) << std::endl;
  if (s.status != RunStatus::kFinished) return kExitRunFailed;
  if ((s.trust == Trust::kLow || missed) && !accept_untrusted) return kExitUntrusted;
  return kExitOk;
}

int RunSimulate(const SimulateOptions& options) {
  // URDF or SDFormat by content; an SDFormat model may close loops, a URDF's <mimic> couple
  // joints (import.loops).
  ModelFileImport import =
      ImportModelFile(options.model_path,
                      UrdfImportOptions{.repair = options.repair,
                                        .max_links = options.max_links,
                                        .couple_mimic = options.couple_mimic,
                                        .floating_base = options.floating_base},
                      options.package_paths);
  for (const std::string& warning : import.warnings) spdlog::warn("{}", warning);
  v1::RunSpec spec;
  std::string source = "(command line)";
  if (!options.spec_path.empty()) {
    spec = LoadRunSpecFile(options.spec_path);
    source = options.spec_path;
  }
  options.overrides.ApplyTo(spec);
  RunConfig config = ToRunConfig(
      spec, SpecCoordinates{PositionNames(import.model), JointNames(import.model)}, source);
  if (!spec.has_gravity()) config.gravity = import.model.gravity;  // an SDF world's <gravity>
  // The server's validation, before anything runs.
  ValidateLoopRun(import.model, import.loops, config);
  CheckRunSize(config, spec.max_output_frames(), options.size);
  WarnServerOnlyFields(spec);
  // Before any integration: legal but absurd inputs (Simulate finds them again for stats.json).
  for (const InputWarning& warning : CheckInputSanity(import.model, config)) {
    std::cerr << "mbstream simulate: warning: " << warning.message << "\n";
  }

  // The CSVs are written as the frames come: memory does not grow with the run.
  ResultsStreamWriter writer(options.out_dir);
  FrameSinks sinks;
  sinks.Add(&writer);
  std::optional<mcap::RunMcapWriter> mcap_writer;
  if (!options.mcap_path.empty()) {
    mcap::RunMcapOptions mcap_options;
    mcap_options.compression = mcap::ParseCompression(options.mcap_compression);
    mcap_options.start_time_ns = options.mcap_start.empty()
                                     ? mcap::NowNanoseconds()
                                     : mcap::ParseStartTime(options.mcap_start, "--mcap-start");
    mcap_writer.emplace(options.mcap_path, import.model, ReadModelText(options.model_path),
                        mcap_options);
    sinks.Add(&*mcap_writer);
  }
  const RunResult result = Simulate(import.model, import.loops, config, &sinks);
  const RunProvenance provenance{import.model.name, options.model_path,
                                 RunSpecToJson(ToRunSpec(config)), "", ""};
  writer.Finish(result, provenance);
  if (mcap_writer) {
    mcap_writer->Finish({}, StatsJson(result, provenance, writer.frames()), result.stats.t_reached);
  }

  PrintSummary(result.stats, writer.frames(), options.out_dir);
  if (mcap_writer) {
    std::cout << "MCAP in " << options.mcap_path << " (" << mcap_writer->bytes_written()
              << " bytes)\n";
  }
  return ExitCodeOf(result.stats, options.accept_untrusted);
}

}  // namespace

void AddSimulateCommand(CLI::App& app, int* exit_code) {
  auto options = std::make_shared<SimulateOptions>();
  CLI::App* command = app.add_subcommand(
      "simulate", "run the engine in-process (no server) and write the results files");
  command
      ->add_option("model", options->model_path,
                   "the model's URDF or SDFormat file, or an SDFormat world")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("--spec", options->spec_path, "run spec (protobuf JSON of RunSpec)")
      ->check(CLI::ExistingFile);
  command->add_option("--out", options->out_dir, "results directory")->required();
  options->overrides.AddTo(*command);
  command->add_option("--mcap", options->mcap_path,
                      "also write the run as one MCAP file (ROS 2 topics /joint_states, /tf, "
                      "/robot_description; docs/mcap.md)");
  command
      ->add_option("--mcap-compression", options->mcap_compression,
                   "the MCAP file's chunk compression: zstd, lz4 or none")
      ->capture_default_str();
  command->add_option("--mcap-start", options->mcap_start,
                      "the MCAP stamps' time of t = 0, UTC: 2026-11-26T12:00:00Z or seconds "
                      "since the Unix epoch (default: the run's start)");
  command->add_flag("--accept-untrusted", options->accept_untrusted,
                    "exit 0 even when the finished run's trust is low or it missed its accuracy "
                    "target (else exit 4)");
  command
      ->add_option("--max-links", options->max_links,
                   "most links and points of the model (as mbstream-server --max-links)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  command
      ->add_option("--max-duration", options->size.max_duration_s,
                   "longest simulated time of the run, s (as mbstream-server)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  command
      ->add_option("--max-output-frames", options->size.max_output_frames,
                   "most frames of the run (as mbstream-server)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  command->add_flag("--repair", options->repair, kRepairHelp);
  command->add_flag("--couple-mimic", options->couple_mimic, kCoupleMimicHelp);
  command->add_flag("--floating-base", options->floating_base, kFloatingBaseHelp);
  command
      ->add_option("--package-path", options->package_paths,
                   "a folder searched for the models of a world's model:// includes (before "
                   "$MBSTREAM_PACKAGE_PATH, colon separated)")
      ->check(CLI::ExistingDirectory);
  command->callback([options, exit_code] {
    try {
      *exit_code = RunSimulate(*options);
    } catch (const InputError& error) {
      std::cerr << "mbstream simulate: " << error.what() << "\n";
      *exit_code = 2;
    }
  });
}

}  // namespace mbstream::cli
