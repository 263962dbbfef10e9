// fleetnav-loadgen: N agents streaming telemetry at R Hz plus M operators submitting and
// watching jobs against a running fleetnavd on loopback; prints one JSON object.
#include <grpcpp/create_channel.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>

#include "absl/synchronization/mutex.h"
#include "fleetnav/core/version.hpp"
#include "fleetnav/proto/server_target.hpp"
#include "fleetnav/v1/fleet_service.grpc.pb.h"
#include "load_agents.hpp"
#include "load_operators.hpp"
#include "load_report.hpp"
#include "load_stops.hpp"
#include "load_tls.hpp"

namespace {

using fleetnav::loadgen::IdleWatchers;
using fleetnav::loadgen::OperatorOptions;
using fleetnav::loadgen::OperatorProcess;
using fleetnav::loadgen::OperatorReport;
using fleetnav::loadgen::SteadyNowNs;
namespace v1 = fleetnav::v1;

}  // namespace

int main(int argc, char** argv) {
  std::string server = "127.0.0.1:50051", tls_dir;
  int agents = 100, submitters = 2, threads = 2, streams_per_connection = 250;
  double rate_hz = 10.0, duration_s = 10.0, submit_rate_hz = 20.0;
  pid_t server_pid = 0;
  bool json = false;
  int capable_agents = 0, idle_watchers = 0, stop_rounds = 0;
  double stop_every_s = 1.0;
  OperatorOptions operator_options;
  CLI::App app{"fleetnav-loadgen: load fleetnavd with agents and operators"};
  app.set_version_flag("--version", std::string(fleetnav::Version()));
  app.add_option("--server", server, "fleetnavd address")->capture_default_str();
  app.add_option("--agents", agents, "agent streams")->capture_default_str();
  app.add_option("--rate-hz", rate_hz, "telemetry per agent per second")->capture_default_str();
  app.add_option("--duration-s", duration_s, "measured time")->capture_default_str();
  app.add_option("--submitters", submitters, "operators submitting jobs")->capture_default_str();
  app.add_option("--submit-rate-hz", submit_rate_hz, "jobs per submitter per second")
      ->capture_default_str();
  app.add_option("--threads", threads, "loadgen threads pacing the agents")->capture_default_str();
  app.add_option("--streams-per-connection", streams_per_connection,
                 "agent streams multiplexed on one connection")
      ->capture_default_str();
  app.add_option("--server-pid", server_pid, "fleetnavd's pid, for its CPU and memory");
  app.add_flag("--json", json, "print one JSON object (the only output mode)");
  app.add_option("--tls-dir", tls_dir,
                 "a TLS fleetnavd: the folder deploy/certs/make-dev-certs wrote with a robot "
                 "certificate per agent (load-0 ...); each agent then has a connection of its "
                 "own and the operators send admin.token (they store the site too)");
  app.add_option("--capable-agents", capable_agents,
                 "agents that advertise `straight`, so the submitted jobs are assigned to them "
                 "(each keeps one); the watched jobs are then timed until ASSIGNED")
      ->capture_default_str();
  app.add_flag("--large-site", operator_options.site.large,
               "store a 100,000-marker set and make the jobs' route 10,000 actions long");
  app.add_option("--big-map-mb", operator_options.site.big_map_mb,
                 "store a second map of this many MB and submit goal jobs on it at 5 Hz")
      ->capture_default_str();
  app.add_option("--submit-retry-s", operator_options.retry_s,
                 "send a failed submission again (same idempotency key) for up to this long")
      ->capture_default_str();
  app.add_option("--acked-jobs", operator_options.acked_path,
                 "append each acknowledged job to this file as 'idempotency_key job_id'");
  app.add_option("--watch-every", operator_options.watch_every, "watch every N-th job")
      ->capture_default_str();
  app.add_option("--idle-watchers", idle_watchers,
                 "open this many WatchJob streams on a job that stays queued and as many "
                 "WatchFleet streams, and keep them open (idle) for the run")
      ->capture_default_str();
  app.add_option("--stop-rounds", stop_rounds,
                 "stop the whole fleet this many times during the run (StopRobots, cleared "
                 "half-way to the next) and time how soon each agent hears it")
      ->capture_default_str();
  app.add_option("--stop-every-s", stop_every_s, "time between stop rounds")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  // Debian's abseil checks lock order on every absl::Mutex use (gRPC's too): measure without.
  absl::SetMutexDeadlockDetectionMode(absl::OnDeadlockCycle::kIgnore);
  if (agents < 0 || submitters < 0 || !(rate_hz > 0) || !(duration_s > 0) || threads < 1 ||
      streams_per_connection < 1 || capable_agents < 0 || idle_watchers < 0 ||
      operator_options.watch_every < 1 || operator_options.site.big_map_mb < 0 ||
      (idle_watchers > 0 && submitters == 0) || stop_rounds < 0 || !(stop_every_s > 0) ||
      (stop_rounds > 0 && (agents == 0 || stop_rounds * stop_every_s > duration_s))) {
    std::cerr << "fleetnav-loadgen: --agents/--submitters must be >= 0, rates and duration > 0, "
                 "--threads and --streams-per-connection >= 1, --watch-every >= 1; "
                 "--idle-watchers needs a submitter (the operators prepare the site); "
                 "--stop-rounds needs agents and rounds x --stop-every-s (> 0) within "
                 "--duration-s\n";
    return 2;
  }

  OperatorProcess operators;
  operator_options.submitters = submitters;
  operator_options.rate_hz = submit_rate_hz;
  operator_options.until_assigned = capable_agents > 0;
  if (server_pid == 0) {
    // No --server-pid: the process listening on the server's port, if it runs here.
    const size_t colon = server.rfind(':');
    if (colon != std::string::npos) {
      server_pid = std::max<pid_t>(
          0, fleetnav::loadgen::ListeningPid(std::atoi(server.substr(colon + 1).c_str())));
    }
  }
  absl::StatusOr<std::string> server_target = fleetnav::ServerTarget(server);
  if (!server_target.ok()) {
    std::cerr << "fleetnav-loadgen: --server: " << server_target.status().message() << '\n';
    return 2;
  }
  const fleetnav::loadgen::LoadTarget target{*server_target, tls_dir};
  if (submitters > 0 && !operators.Start(target, operator_options)) {
    std::cerr << "fleetnav-loadgen: cannot reach fleetnavd at " << server << '\n';
    return 1;
  }

  // Agents: each worker thread paces, writes and reaps its own share on its own completion
  // queue; the agents of one worker are interleaved with the others' in send order.
  // No agents (a pure SubmitJob load): no workers; the run then lasts duration_s by the clock.
  const int worker_count = agents > 0 ? std::clamp(threads, 1, agents) : 0;
  std::vector<std::unique_ptr<fleetnav::loadgen::LoadWorker>> workers;
  for (int w = 0; w < worker_count; ++w) {
    fleetnav::loadgen::WorkerParams params;
    params.target = target;
    params.agents = agents;
    for (int i = w; i < agents; i += worker_count) params.indices.push_back(i);
    params.streams_per_connection = streams_per_connection;
    params.first_channel_index = w * 10000;
    params.capable_agents = capable_agents;
    workers.push_back(std::make_unique<fleetnav::loadgen::LoadWorker>(std::move(params)));
  }
  const int64_t period_ns = static_cast<int64_t>(1e9 / rate_hz);
  std::atomic<int> ready{0}, connected_workers{0}, reported_workers{0};
  std::atomic<int64_t> start_ns{0};
  std::atomic<bool> release{false};
  std::vector<fleetnav::loadgen::WorkerReport> reports(worker_count);
  std::vector<std::thread> worker_threads;
  const int64_t connect_start_ns = SteadyNowNs();
  for (int w = 0; w < worker_count; ++w) {
    worker_threads.emplace_back([&, w] {
      fleetnav::loadgen::LoadWorker& worker = *workers[w];
      ready += worker.Connect(SteadyNowNs() + 60'000'000'000);
      ++connected_workers;
      while (start_ns.load() == 0) worker.Idle(SteadyNowNs() + 5'000'000);
      const int64_t end_ns = start_ns.load() + static_cast<int64_t>(duration_s * 1e9);
      worker.Run(start_ns.load(), end_ns, period_ns, end_ns + 200'000'000);
      reports[w] = worker.TakeReport();
      ++reported_workers;
      while (!release.load()) worker.Idle(SteadyNowNs() + 5'000'000);
      worker.Stop();
    });
  }
  while (connected_workers.load() < worker_count) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  const double connect_s = (SteadyNowNs() - connect_start_ns) * 1e-9;
  IdleWatchers watchers;
  if (idle_watchers > 0) watchers.Open(target, idle_watchers);

  // Pacing: every agent gets one message per period, spread evenly across the period; the
  // workers start together and keep reaping completions for 200 ms after the last message.
  const double cpu_start = server_pid > 0 ? fleetnav::loadgen::ProcessCpuSeconds(server_pid) : -1;
  const int64_t run_start_ns = SteadyNowNs() + 20'000'000;
  start_ns.store(run_start_ns);
  if (submitters > 0) operators.Go();
  std::vector<fleetnav::loadgen::StopRound> stop_rounds_made;
  std::thread stopper;
  if (stop_rounds > 0) {
    const auto every_ns = static_cast<int64_t>(stop_every_s * 1e9);
    stopper = std::thread([&, every_ns] {
      stop_rounds_made = fleetnav::loadgen::RunStopRounds(target, stop_rounds,
                                                          run_start_ns + every_ns / 4, every_ns);
    });
  }
  if (worker_count == 0) {
    std::this_thread::sleep_until(std::chrono::steady_clock::now() +
                                  std::chrono::nanoseconds(run_start_ns - SteadyNowNs()) +
                                  std::chrono::duration<double>(duration_s));
  }
  while (reported_workers.load() < worker_count) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  if (stopper.joinable()) stopper.join();
  const double elapsed_s = (SteadyNowNs() - run_start_ns) * 1e-9;
  const double cpu_end = server_pid > 0 ? fleetnav::loadgen::ProcessCpuSeconds(server_pid) : -1;
  const double rss_mb = server_pid > 0 ? fleetnav::loadgen::ProcessRssMb(server_pid) : -1;
  const OperatorReport submit = submitters > 0 ? operators.Stop() : OperatorReport{};
  release.store(true);
  for (std::thread& t : worker_threads) t.join();
  workers.clear();
  uint64_t delivered = 0, skipped = 0, scheduled = 0;
  std::vector<double> latencies;
  std::vector<std::pair<int, int64_t>> stops_heard;
  for (fleetnav::loadgen::WorkerReport& report : reports) {
    stops_heard.insert(stops_heard.end(), report.stops_heard.begin(), report.stops_heard.end());
    delivered += report.delivered;
    skipped += report.skipped;
    scheduled += report.scheduled;
    latencies.insert(latencies.end(), report.lag_ms.begin(), report.lag_ms.end());
  }

  nlohmann::json out = {
      {"agents", agents},
      {"agents_connected", ready.load()},
      {"connect_s", connect_s},
      {"loadgen_threads", worker_count},
      {"streams_per_connection", streams_per_connection},
      {"rate_hz", rate_hz},
      {"duration_s", elapsed_s},
      {"telemetry_msgs_per_s", delivered / elapsed_s},
      {"telemetry_target_msgs_per_s", agents * rate_hz},
      {"telemetry_skipped_fraction", scheduled ? static_cast<double>(skipped) / scheduled : 0.0},
      {"telemetry_delivered_fraction",
       scheduled ? static_cast<double>(delivered) / scheduled : 0.0},
      {"telemetry_lag_ms_p50", fleetnav::loadgen::Percentile(latencies, 50)},
      {"telemetry_lag_ms_p99", fleetnav::loadgen::Percentile(latencies, 99)},
      {"submitters", submitters},
      {"jobs_submitted", submit.submit_ms.size()},
      {"submit_errors", submit.submit_errors},
      {"watches", submit.watches},
      {"submit_ms_p50", fleetnav::loadgen::Percentile(submit.submit_ms, 50)},
      {"submit_ms_p99", fleetnav::loadgen::Percentile(submit.submit_ms, 99)},
      {"submit_ms_max", fleetnav::loadgen::Percentile(submit.submit_ms, 100)},
      {"capable_agents", capable_agents},
      {"dispatch_ms_p50", fleetnav::loadgen::Percentile(submit.dispatch_ms, 50)},
      {"dispatch_ms_p99", fleetnav::loadgen::Percentile(submit.dispatch_ms, 99)},
      {"dispatch_samples", submit.dispatch_ms.size()},
      {"big_map_mb", operator_options.site.big_map_mb},
      {"big_submit_ms_p50", fleetnav::loadgen::Percentile(submit.big_submit_ms, 50)},
      {"big_submit_ms_p99", fleetnav::loadgen::Percentile(submit.big_submit_ms, 99)},
      {"large_site", operator_options.site.large},
      {"idle_watchers_open", watchers.open()},
      {"server_cpu_percent", cpu_start >= 0 ? 100.0 * (cpu_end - cpu_start) / elapsed_s : -1.0},
      {"server_rss_mb", rss_mb}};
  if (stop_rounds > 0) {
    const fleetnav::loadgen::StopLatency stops =
        fleetnav::loadgen::MeasureStopLatency(stop_rounds_made, stops_heard, agents);
    int failed = 0;
    std::string first_error;
    for (const auto& round : stop_rounds_made) {
      if (round.ok) continue;
      if (failed++ == 0) first_error = round.error;
    }
    out["stop_rounds"] = stop_rounds;
    out["stop_rounds_failed"] = failed;
    out["stop_first_error"] = first_error;
    out["stop_heard"] = stops.heard;
    out["stop_missed"] = stops.missed;
    out["stop_rpc_ms_p50"] = fleetnav::loadgen::Percentile(stops.rpc_ms, 50);
    out["stop_rpc_ms_p99"] = fleetnav::loadgen::Percentile(stops.rpc_ms, 99);
    out["stop_heard_after_return_ms_p50"] = fleetnav::loadgen::Percentile(stops.from_return_ms, 50);
    out["stop_heard_after_return_ms_p99"] = fleetnav::loadgen::Percentile(stops.from_return_ms, 99);
    out["stop_heard_after_return_ms_max"] =
        fleetnav::loadgen::Percentile(stops.from_return_ms, 100);
  }
  std::cout << out.dump() << std::endl;
  return 0;
}
