#include "server/app/server_flags.h"

#include <algorithm>
#include <string>
#include <vector>

#include "server/runs/retention.h"
#include "shared/common/check.h"

namespace mbstream {

ServerFlags::ServerFlags(const ServerConfig& config)
    : max_model_mb(static_cast<double>(config.limits.max_model_bytes) / (1 << 20)),
      max_asset_mb(static_cast<double>(config.limits.max_asset_bytes) / (1 << 20)),
      max_models_mb(static_cast<double>(config.limits.max_total_model_bytes) / (1 << 20)),
      max_message_mb(static_cast<double>(config.max_message_bytes) / (1 << 20)),
      min_free_mb(static_cast<double>(config.limits.min_free_bytes) / (1 << 20)) {}

namespace {

// Where the server listens and stores, and how many runs and streams it serves at once.
void AddServingFlags(CLI::App& app, ServerConfig* config) {
  ServerLimits* limits = &config->limits;
  app.add_option("--listen", config->listen,
                 "host:port (port 0 = any free port, printed) or unix:/path")
      ->capture_default_str();
  CLI::Option* data = app.add_option("--data", config->data_dir,
                                     "directory of the SQLite store (as --store sqlite:DIR)")
                          ->capture_default_str();
  app.add_option("--store", config->store,
                 "sqlite:DIRECTORY, or postgresql://user@host:port/database for several "
                 "servers on one database")
      ->excludes(data);
  app.add_option("--store-password-file", config->store_password_file,
                 "file holding the PostgreSQL password (default: PGPASSFILE, ~/.pgpass)")
      ->check(CLI::ExistingFile);
  app.add_option("--models", config->models_dir,
                 "directory of built-in models (one folder per model); \"\" = none")
      ->capture_default_str();
  app.add_option("--workers", limits->workers, "runs integrating at the same time")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  app.add_option("--max-queued-runs", limits->max_queued_runs, "runs waiting for a worker")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  app.add_option("--max-subscribers", limits->max_subscribers, "Subscribe and WatchRun streams")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  app.add_option("--subscribe-start-s", limits->subscribe_start_s,
                 "s a Subscribe stream may take to send its start message")
      ->check(CLI::Range(0.01, 3600.0))
      ->capture_default_str();
  app.add_option("--max-probe-reports", limits->max_probe_reports,
                 "most probe reports kept for one run")
      ->check(CLI::Range(int64_t{1}, int64_t{1} << 40))
      ->capture_default_str();
}

// The size of what a user may send and run (models, runs, messages).
void AddSizeFlags(CLI::App& app, ServerConfig* config, ServerFlags* flags) {
  ServerLimits* limits = &config->limits;
  app.add_option("--max-model-mb", flags->max_model_mb,
                 "largest model bundle (URDF, scene and assets), MiB; the gRPC message limit "
                 "is raised to hold it")
      ->check(CLI::Range(1e-3, 2000.0))
      ->capture_default_str();
  app.add_option("--max-asset-mb", flags->max_asset_mb, "largest asset (mesh file) of a model, MiB")
      ->check(CLI::Range(1e-3, 2000.0))
      ->capture_default_str();
  app.add_option("--max-assets", limits->max_assets, "most assets (mesh files) of a model")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  app.add_option("--max-models", limits->max_models,
                 "most models users may store (built-ins apart)")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  app.add_option("--max-models-mb", flags->max_models_mb,
                 "largest total size of the stored models, MiB")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--model-cache", limits->compiled_models_cached,
                 "compiled models kept in memory (stored models compile on first use)")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  app.add_option("--max-links", limits->max_links, "most links and points of a model")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  app.add_option("--max-duration", limits->max_duration_s, "longest simulated time of a run, s")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--max-output-frames", limits->max_output_frames, "most frames of a run")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--max-run-steps", limits->max_internal_steps,
                 "most internal integrator steps of a run (caps the spec's max_internal_steps "
                 "and the default budget)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--max-run-cpu-s", limits->max_run_cpu_s,
                 "most CPU seconds of a run (caps the spec's max_cpu_s and the default budget)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--frame-flush-s", limits->frame_flush_s,
                 "s of wall time after which a running run's new frames are stored even when "
                 "their 4,096-frame chunk is not full: a crash (kill -9) loses at most this much "
                 "of a run; 0 = only full chunks")
      ->check(CLI::Range(0.0, 3600.0))
      ->capture_default_str();
  app.add_option("--min-free-mb", flags->min_free_mb,
                 "MiB that must stay free on the disk of --data for a new run to start (below: "
                 "refused with RESOURCE_EXHAUSTED): a margin for the runs already running, "
                 "SQLite's journal and checkpoints, so that a full disk refuses runs instead of "
                 "failing them; 0 = no check; not checked for a PostgreSQL --store")
      ->check(CLI::Range(0.0, 1e9))
      ->capture_default_str();
  app.add_option("--max-message-mb", flags->max_message_mb, "largest gRPC message, MiB")
      ->check(CLI::Range(1.0, 2047.0))
      ->capture_default_str();
}

// Retention: which ended runs are deleted in the background, and how often it looks.
void AddRetentionFlags(CLI::App& app, ServerConfig* config) {
  app.add_option("--retain-runs", config->retention.retain_runs,
                 "keep the newest this many ended runs (not counting runs marked keep: "
                 "`mbstream keep`); older ended runs are deleted in the background; 0 = no limit")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--retain-days", config->retention.retain_days,
                 "delete ended runs (not marked keep) that ended more than this many days ago, "
                 "in the background; 0 = no limit; `mbstream retention` lists what goes next")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  app.add_option_function<std::vector<std::string>>(
         "--retain-model",
         [config](const std::vector<std::string>& values) {
           for (const std::string& value : values) AddModelRetention(value, config->retention);
         },
         "MODEL=RUNS[,DAYS] (repeatable): the runs of this model (name or id) are kept by limits "
         "of their own, the newest RUNS ended runs and those ended within DAYS days (0 = no "
         "limit), instead of --retain-runs/--retain-days")
      ->check([](const std::string& value) {
        RetentionPolicy policy;
        try {
          AddModelRetention(value, policy);
          return std::string();
        } catch (const InputError& error) {
          return std::string(error.what());
        }
      });
  app.add_option("--retention-period-s", config->retention_period_s,
                 "s between two passes of retention (--retain-runs, --retain-days)")
      ->check(CLI::Range(0.01, 86400.0))
      ->capture_default_str();
}

// TLS, tokens, the cluster's replicas, draining, metrics and logging.
void AddSecurityAndClusterFlags(CLI::App& app, ServerConfig* config, ServerFlags* flags) {
  app.add_option("--tls-cert", config->tls.cert_file, "PEM certificate chain (enables TLS)")
      ->check(CLI::ExistingFile);
  app.add_option("--tls-key", config->tls.key_file, "PEM private key of --tls-cert")
      ->check(CLI::ExistingFile);
  app.add_option("--tls-client-ca", config->tls.client_ca_file,
                 "PEM CA; clients must then present a certificate it signed")
      ->check(CLI::ExistingFile);
  app.add_option("--token-file", config->token_file,
                 "tokens and roles, one `<token> <role>[,<role>]` per line (submit, run, view, "
                 "admin)")
      ->check(CLI::ExistingFile);
  app.add_option("--peer-ca", config->peer_ca,
                 "PEM CA trusted for the other replicas' certificates when calls about their "
                 "runs are proxied to them (TLS; default: --tls-client-ca, else the system's CAs)")
      ->check(CLI::ExistingFile);
  app.add_option("--peer-tls-name", config->peer_tls_name,
                 "name checked in the other replicas' certificates (default: the host of their "
                 "advertised address; give the shared certificate's name when they share one)");
  app.add_option("--advertise", config->advertise,
                 "host:port other replicas and clients reach this server at (default: the "
                 "listening address)");
  app.add_option("--lease-timeout-s", config->lease_timeout_s,
                 "s after which the run of a replica that stopped renewing its lease is "
                 "reaped by another (INTERRUPTED, or queued again with spec.retries)")
      ->check(CLI::Range(0.1, 3600.0))
      ->capture_default_str();
  app.add_option("--grace-s", config->grace_s,
                 "s a draining server (SIGTERM) gives its runs to end before handing them back")
      ->check(CLI::Range(0.0, 86400.0))
      ->capture_default_str();
  app.add_option("--metrics", config->metrics,
                 "host:port serving Prometheus metrics over plain HTTP at GET /metrics (port 0 = "
                 "any free port, printed); give a loopback or private address")
      ->check([](const std::string& value) {
        return value.rfind(':') == std::string::npos ? "expected host:port" : "";
      });
  app.add_option("--log-level", flags->log_level, "trace, debug, info, warn, error")
      ->capture_default_str();
}

}  // namespace

void ServerFlags::AddTo(CLI::App& app, ServerConfig* config) {
  AddServingFlags(app, config);
  AddSizeFlags(app, config, this);
  AddRetentionFlags(app, config);
  AddSecurityAndClusterFlags(app, config, this);
}

void ServerFlags::Apply(ServerConfig* config) const {
  ServerLimits* limits = &config->limits;
  limits->max_model_bytes = static_cast<int64_t>(max_model_mb * (1 << 20));
  limits->max_asset_bytes = static_cast<int64_t>(max_asset_mb * (1 << 20));
  // A bundle travels in one SubmitModel message: the message limit holds the largest one
  // (plus 1 MiB for the request's other fields and framing).
  config->max_message_bytes =
      static_cast<int>(std::min(2047.0, std::max(max_message_mb, max_model_mb + 1.0)) * (1 << 20));
  limits->max_total_model_bytes = static_cast<int64_t>(std::min(max_models_mb, 1e12) * (1 << 20));
  limits->min_free_bytes = static_cast<int64_t>(min_free_mb * (1 << 20));
}

}  // namespace mbstream
