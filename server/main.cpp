// fleetnavd: the fleet server. Wiring only: config file and flags -> FleetServer -> serve until
// SIGINT/SIGTERM.
#include <pthread.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <cstdlib>

#include "absl/strings/str_cat.h"
#include "absl/synchronization/mutex.h"
#include "fleetnav/core/port_file.hpp"
#include "fleetnav/core/stop_signals.hpp"
#include "fleetnav/core/version.hpp"
#include "fleetnav/server/http/http_gateway.hpp"
#include "fleetnav/server/log/log_format.hpp"
#include "fleetnav/server/replica/replica_server.hpp"
#include "fleetnav/server/rpc/fleet_server.hpp"
#include "fleetnav/server/rpc/fleet_server_config.hpp"
#include "fleetnav/storage/postgres/pg_database.hpp"
#include "fleetnav/storage/sqlite/schema.hpp"
#include "fleetnav/storage/sqlite/sqlite_database.hpp"

namespace {

/// `fleetnavd --check-db`: reads the database without writing to it and prints what it found.
int CheckDatabase(const std::string& path) {
  if (fleetnav::storage::IsPostgresUri(path)) {
    std::fprintf(stderr,
                 "fleetnavd: --check-db reads SQLite files; check a PostgreSQL database with its "
                 "own tools (pg_amcheck)\n");
    return 2;
  }
  absl::StatusOr<fleetnav::storage::SqliteCheckReport> report =
      fleetnav::storage::SqliteDatabase::Check(path, fleetnav::storage::FleetDatabaseOptions());
  if (!report.ok()) {
    std::fprintf(stderr, "fleetnavd: %s\n", report.status().ToString().c_str());
    return 2;
  }
  const int binary_version = static_cast<int>(fleetnav::storage::FleetSchemaMigrations().size());
  if (report->schema_version > binary_version) {
    report->problems.push_back(absl::StrCat("schema version ", report->schema_version,
                                            " is newer than this binary's ", binary_version));
  }
  std::printf("database '%s': schema version %d (this binary %d)\n", path.c_str(),
              report->schema_version, binary_version);
  for (const std::string& problem : report->problems)
    std::printf("  problem: %s\n", problem.c_str());
  std::printf("%s\n", report->ok() ? "ok" : "damaged or not a fleetnav database");
  return report->ok() ? 0 : 1;
}

/// Exit code of a replica that lost the site's leadership it held (docs/server.md).
constexpr int kLeadershipLostExitCode = 3;

/// What `--replica` adds to the server's parameters.
struct ReplicaFlags {
  std::string site = "default";
  std::string peer_listen;
  std::string peer_advertise;
  std::string peer_http_listen;
  double lease_ttl_s = 2.0;
};

/// `fleetnavd --replica`: one of several replicas sharing a PostgreSQL database; serves the
/// public port until SIGINT/SIGTERM, and ends the process with kLeadershipLostExitCode when it
/// loses the leadership it held.
int RunReplica(const fleetnav::server::FleetServerParams& params, const ReplicaFlags& flags,
               const std::string& http_listen, const std::string& port_file,
               const std::string& http_port_file, sigset_t* stop_signals) {
  fleetnav::server::ReplicaParams replica;
  replica.leader = params;
  replica.listen_address = params.listen_address;
  const std::string listen_host = params.listen_address.substr(0, params.listen_address.rfind(':'));
  replica.leader.listen_address =
      flags.peer_listen.empty() ? listen_host + ":0" : flags.peer_listen;
  replica.advertise_address = flags.peer_advertise;
  replica.http_listen_address = http_listen;
  replica.leader_http_listen_address = flags.peer_http_listen;
  replica.leadership =
      fleetnav::server::SiteLeadershipParams::ForTtl(flags.site, flags.lease_ttl_s);
  replica.on_event = [](const std::string& what) { spdlog::info("fleetnavd: {}", what); };
  replica.on_leadership_lost = [](const std::string& why) {
    // Nothing more may be done as leader; the store is fenced, and the robots reconnect
    // through the other replicas.
    spdlog::error("fleetnavd: leadership lost: {}; exiting", why);
    spdlog::default_logger()->flush();
    std::_Exit(kLeadershipLostExitCode);
  };
  if (absl::Status valid = replica.Validate(); !valid.ok()) {
    spdlog::error("fleetnavd: {}", valid.ToString());
    return 2;
  }
  fleetnav::server::ReplicaServer server(replica);
  absl::StatusOr<int> port = server.Start();
  if (!port.ok()) {
    spdlog::error("fleetnavd: {}", port.status().ToString());
    return 1;
  }
  spdlog::info("fleetnavd replica {} serving on port {} for site '{}' (db {}, {})", server.holder(),
               *port, flags.site, server.store_description(),
               server.secure() ? "TLS, robot certificates and operator tokens"
                               : "INSECURE: plaintext, no authentication");
  if (server.http_port() > 0) {
    spdlog::info("fleetnavd dashboard and /metrics on {}://{}:{}/ (relayed to the leader's)",
                 server.secure() ? "https" : "http", http_listen.substr(0, http_listen.rfind(':')),
                 server.http_port());
    if (!http_port_file.empty()) {
      if (absl::Status written = fleetnav::WritePortFile(http_port_file, server.http_port());
          !written.ok()) {
        spdlog::warn("fleetnavd: {}", std::string(written.message()));
      }
    }
  }
  if (!port_file.empty()) {
    if (absl::Status written = fleetnav::WritePortFile(port_file, *port); !written.ok()) {
      spdlog::warn("fleetnavd: {}", std::string(written.message()));
    }
  }
  int signal_number = 0;
  sigwait(stop_signals, &signal_number);
  spdlog::info("fleetnavd: signal {}, shutting down", signal_number);
  server.Shutdown();
  return 0;
}

/// Every flag of fleetnavd; a flag left unset keeps the config file's value (or the default).
struct Flags {
  std::string config_path, listen, db, log_level, port_file, clock = "system", sim_address;
  std::string http_listen, http_port_file, log_format_text = "text";
  double stale_after_s = 0, lost_robot_timeout_s = 0, db_wait_s = -1;
  bool check_db = false, insecure = false, replica = false;
  ReplicaFlags replica_flags;
  fleetnav::server::ServerSecurityFiles tls;
  int max_message_bytes = 0, agent_threads = 0;
};

void AddFlags(CLI::App& app, Flags* f) {
  app.add_option("--config", f->config_path, "YAML configuration file (see docs/server.md)");
  app.add_option("--listen", f->listen,
                 "address to serve on (host:port; port 0 = any) [127.0.0.1:50051]");
  app.add_option("--db", f->db,
                 "SQLite database file (created if missing) or a postgresql://USER@HOST:PORT/DB "
                 "URI [fleetnav.db]");
  app.add_option("--db-wait-s", f->db_wait_s,
                 "with PostgreSQL: how long to keep trying to reach the database at start [10]");
  app.add_option("--stale-after-s", f->stale_after_s,
                 "seconds without telemetry before a robot is stale [2]");
  app.add_option("--lost-robot-timeout-s", f->lost_robot_timeout_s,
                 "seconds a paused job waits for its robot before failing or re-queueing [30]");
  app.add_option("--max-message-bytes", f->max_message_bytes,
                 "largest request accepted [67108864]");
  app.add_option("--agent-threads", f->agent_threads,
                 "threads serving robot streams, each with its own completion queue [2]");
  app.add_option("--log-level", f->log_level, "trace|debug|info|warn|error [info]");
  app.add_option("--log-format", f->log_format_text,
                 "text, or json: one JSON object per line (ts, level, msg and fields such as "
                 "job_id and robot_id)")
      ->check(CLI::IsMember({"text", "json"}))
      ->capture_default_str();
  app.add_option("--http-listen", f->http_listen,
                 "serve the web dashboard, its API and /metrics on host:port (HTTPS with the TLS "
                 "files; port 0 = any) [off]");
  app.add_option("--http-port-file", f->http_port_file,
                 "write the HTTP port to this file once serving");
  app.add_option("--tls-cert", f->tls.cert_path, "the server's certificate chain (PEM)");
  app.add_option("--tls-key", f->tls.key_path, "the server certificate's private key (PEM)");
  app.add_option("--tls-client-ca", f->tls.client_ca_path,
                 "the CA that signs robot certificates (PEM); a robot's certificate common name "
                 "is its robot id");
  app.add_option("--tokens", f->tls.tokens_path,
                 "operator tokens with their roles (YAML, see docs/security.md)");
  app.add_flag("--insecure", f->insecure,
               "serve plaintext without authentication (demo and tests only): any client can "
               "drive robots");
  app.add_option("--port-file", f->port_file, "write the bound port to this file once serving");
  app.add_option("--clock", f->clock,
                 "time source of timeouts and pose history: system, or sim (the simulator's "
                 "time, read from --sim) [system]")
      ->check(CLI::IsMember({"system", "sim"}));
  app.add_option("--sim", f->sim_address, "the simulator's SimService address, for --clock sim");
  app.add_flag("--check-db", f->check_db,
               "check the database file (ownership, PRAGMA integrity_check, schema version) "
               "without writing to it, print the findings and exit: 0 sound, 1 problems found, "
               "2 unreadable");
  app.add_flag("--replica", f->replica,
               "one of several fleetnavd sharing a PostgreSQL --db: serve the public port and "
               "relay to the site's leader, elected among the replicas (docs/server.md)");
  app.add_option("--site", f->replica_flags.site, "with --replica: the site the replicas serve")
      ->capture_default_str();
  app.add_option("--peer-listen", f->replica_flags.peer_listen,
                 "with --replica: the leader port the other replicas relay to [--listen's "
                 "host, any port]");
  app.add_option("--peer-advertise", f->replica_flags.peer_advertise,
                 "with --replica: host:port the other replicas reach the leader port at "
                 "[--peer-listen's host and bound port]");
  app.add_option("--peer-http-listen", f->replica_flags.peer_http_listen,
                 "with --replica and --http-listen: where the leader serves its dashboard to the "
                 "other replicas' HTTP ports [--peer-listen's host, any port]");
  app.add_option("--lease-ttl-s", f->replica_flags.lease_ttl_s,
                 "with --replica: a leader silent this long is replaced")
      ->capture_default_str();
}

/// The config file's parameters with the flags over them; InvalidArgument (exit code 2) for a
/// bad file or flags that exclude each other.
absl::StatusOr<fleetnav::server::FleetServerConfig> Configure(Flags& flags) {
  if ((flags.clock == "sim") != !flags.sim_address.empty()) {
    return absl::InvalidArgumentError(
        "--clock sim needs --sim ADDR, and --sim is only used with --clock sim");
  }
  fleetnav::server::FleetServerConfig defaults;
  absl::StatusOr<fleetnav::server::FleetServerConfig> config =
      flags.config_path.empty()
          ? absl::StatusOr<fleetnav::server::FleetServerConfig>(defaults)
          : fleetnav::server::LoadFleetServerConfig(flags.config_path, defaults);
  if (!config.ok()) return config.status();
  fleetnav::server::FleetServerParams& params = config->params;
  if (!flags.listen.empty()) params.listen_address = flags.listen;
  if (!flags.db.empty()) params.db_path = flags.db;
  if (flags.db_wait_s >= 0) params.postgres.connect_wait_s = flags.db_wait_s;
  if (flags.stale_after_s > 0) params.registry.stale_after_s = flags.stale_after_s;
  if (flags.lost_robot_timeout_s > 0) {
    params.jobs.lost_robot_timeout_s = flags.lost_robot_timeout_s;
  }
  if (flags.max_message_bytes > 0) params.max_message_bytes = flags.max_message_bytes;
  if (flags.agent_threads > 0) params.agent_stream_threads = flags.agent_threads;
  params.sim_clock_address = flags.sim_address;
  if (!flags.log_level.empty()) config->log_level = flags.log_level;
  if (!flags.tls.cert_path.empty()) params.security.cert_path = flags.tls.cert_path;
  if (!flags.tls.key_path.empty()) params.security.key_path = flags.tls.key_path;
  if (!flags.tls.client_ca_path.empty()) params.security.client_ca_path = flags.tls.client_ca_path;
  if (!flags.tls.tokens_path.empty()) params.security.tokens_path = flags.tls.tokens_path;
  flags.insecure = flags.insecure || config->insecure;
  if (!flags.check_db && flags.insecure == !params.security.empty()) {
    return absl::InvalidArgumentError(
        flags.insecure ? "--insecure and TLS files (--tls-cert, --tls-key, --tls-client-ca, "
                         "--tokens) exclude each other"
                       : "give --tls-cert, --tls-key, --tls-client-ca and --tokens (see "
                         "docs/security.md), or --insecure to serve plaintext without "
                         "authentication");
  }
  return config;
}

/// The log's level and format, and the server's log lines: each job transition, each refused
/// call, each token change.
void SetUpLogging(const std::string& level, const std::string& format_text,
                  fleetnav::server::FleetServerParams* params) {
  spdlog::set_level(spdlog::level::from_str(level));
  const fleetnav::server::log::LogFormat log_format =
      *fleetnav::server::log::ParseLogFormat(format_text);
  if (log_format == fleetnav::server::log::LogFormat::kJson) {
    spdlog::set_formatter(std::make_unique<fleetnav::server::log::JsonLogFormatter>());
  }
  // One line per job transition, with the job's and robot's ids as fields.
  params->on_job_event = [log_format](const fleetnav::Job& job, const fleetnav::JobEvent& event) {
    if (std::optional<fleetnav::server::log::LogFields> line =
            fleetnav::server::log::JobTransitionLine(job, event)) {
      spdlog::info("{}", fleetnav::server::log::FormatLogPayload(log_format, *line));
    }
  };
  params->on_access_refused = [](const std::string& why) {
    spdlog::warn("fleetnavd: refused: {}", why);
  };
  params->on_token_change = [](const std::string& what) { spdlog::info("fleetnavd: {}", what); };
}

/// The exit lines: calls admitted and refused, and the dispatcher's figures.
void LogExitFigures(const fleetnav::server::FleetServer& server) {
  const fleetnav::server::PassFigures passes = server.assigning_passes();
  const fleetnav::server::PassFigures one_job = server.one_job_passes();
  const fleetnav::server::PassFigures one_job_cpu = server.one_job_pass_cpu();
  const fleetnav::server::PassFigures searches = server.traffic_search_cpu();
  if (server.secure()) {
    const fleetnav::server::AccessCounts access = server.access_counts();
    spdlog::info(
        "fleetnavd: calls admitted {}, unauthenticated {}, denied {}; TLS handshakes refused {}",
        access.admitted, access.unauthenticated, access.denied, access.handshakes_refused);
  }
  // Read by fleetnav-scenario (docs/scenarios.md): keep the wording.
  spdlog::info(
      "fleetnavd: {} assigning dispatch passes, p50 {:.2f} ms, p99 {:.2f} ms, max {:.2f} ms; {} "
      "one-job passes, p50 {:.2f} ms, p99 {:.2f} ms, max {:.2f} ms; one-job pass CPU p50 {:.2f} "
      "ms, p99 {:.2f} ms, max {:.2f} ms; {} traffic searches, CPU p50 {:.2f} ms, p99 {:.2f} ms, "
      "max {:.2f} ms",
      passes.count, passes.p50_ms, passes.p99_ms, passes.max_ms, one_job.count, one_job.p50_ms,
      one_job.p99_ms, one_job.max_ms, one_job_cpu.p50_ms, one_job_cpu.p99_ms, one_job_cpu.max_ms,
      searches.count, searches.p50_ms, searches.p99_ms, searches.max_ms);
}

/// One fleetnavd (not a replica): serves, with the dashboard when asked, until SIGINT/SIGTERM.
int Serve(const fleetnav::server::FleetServerParams& params, const Flags& flags,
          sigset_t* stop_signals) {
  const std::string& http_listen = flags.http_listen;
  const std::string& http_port_file = flags.http_port_file;
  const std::string& port_file = flags.port_file;
  fleetnav::server::FleetServer server(params);
  absl::StatusOr<int> port = server.Start();
  if (!port.ok()) {
    spdlog::error("fleetnavd: {}", port.status().ToString());
    return 1;
  }
  spdlog::info("fleetnavd serving on port {} (db {}, {})", *port, server.store_description(),
               server.secure() ? "TLS, robot certificates and operator tokens"
                               : "INSECURE: plaintext, no authentication");
  std::unique_ptr<fleetnav::server::http::HttpGateway> http;
  if (!http_listen.empty()) {
    fleetnav::server::http::HttpGatewayParams http_params;
    http_params.listen_address = http_listen;
    http_params.cert_path = params.security.cert_path;
    http_params.key_path = params.security.key_path;
    http = std::make_unique<fleetnav::server::http::HttpGateway>(
        &server.app(), [&server] { return server.RenderMetrics(); }, http_params);
    absl::StatusOr<int> http_port = http->Start();
    if (!http_port.ok()) {
      spdlog::error("fleetnavd: {}", http_port.status().ToString());
      server.Shutdown();
      return 1;
    }
    spdlog::info("fleetnavd dashboard and /metrics on {}://{}:{}/",
                 server.secure() ? "https" : "http", http_listen.substr(0, http_listen.rfind(':')),
                 *http_port);
    if (!http_port_file.empty()) {
      if (absl::Status written = fleetnav::WritePortFile(http_port_file, *http_port);
          !written.ok()) {
        spdlog::warn("fleetnavd: {}", std::string(written.message()));
      }
    }
  }
  if (!port_file.empty()) {
    if (absl::Status written = fleetnav::WritePortFile(port_file, *port); !written.ok()) {
      spdlog::warn("fleetnavd: {}", std::string(written.message()));
    }
  }

  int signal_number = 0;
  sigwait(stop_signals, &signal_number);
  spdlog::info("fleetnavd: signal {}, shutting down", signal_number);
  if (http != nullptr) http->Stop();
  server.Shutdown();
  server.Wait();
  LogExitFigures(server);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // Debian's abseil is built with assertions on, so every absl::Mutex acquisition would also
  // update a process-wide lock-order graph (itself behind one global lock): a few percent of the
  // server's time under load, on every telemetry message. Tests keep the detection on.
  absl::SetMutexDeadlockDetectionMode(absl::OnDeadlockCycle::kIgnore);
  // SIGINT/SIGTERM are blocked in every thread and taken synchronously below.
  sigset_t stop_signals = fleetnav::BlockStopSignals();

  // Flags override the config file, which overrides the defaults.
  CLI::App app{"fleetnavd: fleet navigation server (FleetService + AgentService)"};
  app.set_version_flag("--version", std::string(fleetnav::Version()));
  Flags flags;
  AddFlags(app, &flags);
  CLI11_PARSE(app, argc, argv);
  absl::StatusOr<fleetnav::server::FleetServerConfig> config = Configure(flags);
  if (!config.ok()) {
    spdlog::error("fleetnavd: {}", std::string(config.status().message()));
    return 2;
  }
  fleetnav::server::FleetServerParams& params = config->params;
  if (flags.check_db) return CheckDatabase(params.db_path);
  SetUpLogging(config->log_level, flags.log_format_text, &params);
  if (flags.replica) {
    return RunReplica(params, flags.replica_flags, flags.http_listen, flags.port_file,
                      flags.http_port_file, &stop_signals);
  }
  return Serve(params, flags, &stop_signals);
}
