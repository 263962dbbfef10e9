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
#include "load_report.hpp"
#include "load_tls.hpp"

namespace {

using fleetnav::loadgen::SteadyNowNs;
namespace v1 = fleetnav::v1;

std::shared_ptr<grpc::Channel> NewChannel(const fleetnav::loadgen::LoadTarget& target, int index) {
  return fleetnav::loadgen::NewOperatorChannel(target, index);
}

/// What the operators' site holds, beyond a small map and a one-action route.
struct SiteOptions {
  bool large = false;  ///< a 100,000-marker set, and a 10,000-action route for the jobs
  int big_map_mb = 0;  ///< a second map of this many MB, with goal jobs submitted on it
};

constexpr int kLargeMarkers = 100'000;
constexpr int kLargeRouteActions = 10'000;

/// A map and a route for the submitters' jobs (and what `site` asks for).
bool PrepareRoute(v1::FleetService::Stub* fleet, const SiteOptions& site) {
  grpc::ClientContext map_context;
  v1::PutMapRequest map;
  map.set_map_id("loadgen");
  v1::OccupancyGrid* grid = map.mutable_grid();
  grid->set_width(100);
  grid->set_height(100);
  grid->set_resolution_m(0.1);
  grid->set_cells(std::string(100 * 100, '\0'));
  v1::PutMapResponse map_response;
  if (!fleet->PutMap(&map_context, map, &map_response).ok()) return false;
  grpc::ClientContext route_context;
  v1::PutRouteRequest route;
  route.mutable_route()->set_name("loadgen-route");
  route.mutable_route()->set_map_id("loadgen");
  const int actions = site.large ? kLargeRouteActions : 1;
  for (int i = 0; i < actions; ++i) {
    v1::StraightAction* straight = route.mutable_route()->add_actions()->mutable_straight();
    straight->set_distance_m(1.0);
    straight->set_speed_mps(0.2);
  }
  v1::PutRouteResponse route_response;
  if (!fleet->PutRoute(&route_context, route, &route_response).ok()) return false;
  if (site.large) {
    grpc::ClientContext markers_context;
    v1::PutMarkerSetRequest markers;
    markers.mutable_marker_set()->set_map_id("loadgen");
    for (int i = 1; i <= kLargeMarkers; ++i) {
      v1::StripeMarker* marker = markers.mutable_marker_set()->add_markers();
      marker->set_id(i);
      marker->mutable_pose()->set_x_m(0.1 * (i % 100));
      marker->mutable_pose()->set_y_m(0.1 * ((i / 100) % 100));
      marker->set_length_m(0.5);
      marker->set_kind(v1::MARKER_KIND_CALIBRATION);
    }
    v1::PutMarkerSetResponse markers_response;
    if (!fleet->PutMarkerSet(&markers_context, markers, &markers_response).ok()) return false;
  }
  if (site.big_map_mb > 0) {
    const int side = static_cast<int>(std::sqrt(site.big_map_mb * 1e6));
    grpc::ClientContext big_context;
    big_context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(60));
    v1::PutMapRequest big;
    big.set_map_id("loadgen-big");
    big.mutable_grid()->set_width(side);
    big.mutable_grid()->set_height(side);
    big.mutable_grid()->set_resolution_m(0.05);
    big.mutable_grid()->set_cells(std::string(static_cast<size_t>(side) * side, '\0'));
    v1::PutMapResponse big_response;
    if (!fleet->PutMap(&big_context, big, &big_response).ok()) return false;
  }
  // A route no loadgen agent can drive (a turn), for jobs that stay queued under watch.
  grpc::ClientContext idle_context;
  v1::PutRouteRequest idle;
  idle.mutable_route()->set_name("loadgen-idle");
  idle.mutable_route()->set_map_id("loadgen");
  idle.mutable_route()->add_actions()->mutable_turn()->set_angle_rad(1.0);
  idle.mutable_route()->mutable_actions(0)->mutable_turn()->set_yaw_rate_radps(0.3);
  v1::PutRouteResponse idle_response;
  return fleet->PutRoute(&idle_context, idle, &idle_response).ok();
}

/// What the operators measured.
struct OperatorReport {
  std::vector<double> submit_ms;
  std::vector<double> dispatch_ms;    ///< submit -> ASSIGNED event, for watched jobs
  std::vector<double> big_submit_ms;  ///< goal jobs on the big map
  uint64_t submit_errors = 0;
  uint64_t watches = 0;
};

/// How the operators behave.
struct OperatorOptions {
  int submitters = 2;
  double rate_hz = 20.0;
  int watch_every = 10;         ///< every N-th job is watched
  bool until_assigned = false;  ///< watch until ASSIGNED (capable agents exist), else 1st event
  /// A submission refused or lost (a replica killed, a failover) is sent again with the same
  /// idempotency key until it is acknowledged or this much time passed (0: never again).
  double retry_s = 0.0;
  /// Each acknowledged job appended as "idempotency_key job_id" ("": none).
  std::string acked_path;
  SiteOptions site;
};

/// M operators each submitting jobs at `rate_hz` (and watching every tenth job until its first
/// event) until `stop` is set.
OperatorReport RunOperators(const fleetnav::loadgen::LoadTarget& server,
                            const OperatorOptions& options, const std::atomic<bool>& stop) {
  const int submitters = options.submitters;
  const double rate_hz = options.rate_hz;
  std::mutex mutex;
  OperatorReport report;
  std::vector<std::thread> operators;
  std::ofstream acked;
  if (!options.acked_path.empty()) acked.open(options.acked_path, std::ios::app);
  for (int s = 0; s < submitters; ++s) {
    operators.emplace_back([&, s] {
      auto stub = v1::FleetService::NewStub(NewChannel(server, 1000 + s));
      const auto period = std::chrono::duration<double>(1.0 / rate_hz);
      auto next = std::chrono::steady_clock::now();
      for (int i = 0; !stop.load(); ++i) {
        grpc::ClientContext context;
        context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
        v1::SubmitJobRequest request;
        request.set_route_name("loadgen-route");
        request.set_robot_id("");
        request.set_idempotency_key("lg-" + std::to_string(SteadyNowNs()) + "-" +
                                    std::to_string(s) + "-" + std::to_string(i));
        v1::SubmitJobResponse response;
        const int64_t start = SteadyNowNs();
        bool ok = stub->SubmitJob(&context, request, &response).ok();
        while (!ok && !stop.load() && (SteadyNowNs() - start) * 1e-9 < options.retry_s) {
          std::this_thread::sleep_for(std::chrono::milliseconds(100));
          grpc::ClientContext again;
          again.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
          ok = stub->SubmitJob(&again, request, &response).ok();
        }
        const double ms = (SteadyNowNs() - start) * 1e-6;
        if (ok && acked.is_open()) {
          std::lock_guard<std::mutex> lock(mutex);
          acked << request.idempotency_key() << ' ' << response.job().job_id() << '\n';
        }
        if (ok && i % options.watch_every == 0) {
          // Watched until its first event, or until it is assigned to a robot.
          grpc::ClientContext watch_context;
          watch_context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
          v1::WatchJobRequest watch;
          watch.set_job_id(response.job().job_id());
          auto reader = stub->WatchJob(&watch_context, watch);
          v1::JobEvent event;
          bool got = reader->Read(&event);
          while (got && options.until_assigned && event.type() != v1::JOB_EVENT_TYPE_ASSIGNED) {
            got = reader->Read(&event);
          }
          const double dispatch_ms = (SteadyNowNs() - start) * 1e-6;
          watch_context.TryCancel();
          (void)reader->Finish();
          std::lock_guard<std::mutex> lock(mutex);
          report.watches += got;
          if (got && options.until_assigned) report.dispatch_ms.push_back(dispatch_ms);
        }
        {
          std::lock_guard<std::mutex> lock(mutex);
          if (ok) {
            report.submit_ms.push_back(ms);
          } else {
            ++report.submit_errors;
          }
        }
        next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
        std::this_thread::sleep_until(next);
      }
    });
  }
  if (options.site.big_map_mb > 0) {
    // One more operator submits go-to-goal jobs on the big map, 5 a second.
    operators.emplace_back([&] {
      auto stub = v1::FleetService::NewStub(NewChannel(server, 2000));
      auto next = std::chrono::steady_clock::now();
      while (!stop.load()) {
        grpc::ClientContext context;
        context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
        v1::SubmitJobRequest request;
        request.mutable_goal()->set_map_id("loadgen-big");
        request.mutable_goal()->mutable_goal()->set_x_m(1.0);
        request.mutable_goal()->mutable_goal()->set_y_m(1.0);
        v1::SubmitJobResponse response;
        const int64_t start = SteadyNowNs();
        const bool ok = stub->SubmitJob(&context, request, &response).ok();
        const double ms = (SteadyNowNs() - start) * 1e-6;
        {
          std::lock_guard<std::mutex> lock(mutex);
          if (ok) {
            report.big_submit_ms.push_back(ms);
          } else {
            ++report.submit_errors;
          }
        }
        next += std::chrono::milliseconds(200);
        std::this_thread::sleep_until(next);
      }
    });
  }
  for (std::thread& t : operators) t.join();
  return report;
}

bool WriteAll(int fd, const std::string& data) {
  for (size_t done = 0; done < data.size();) {
    const ssize_t n = write(fd, data.data() + done, data.size() - done);
    if (n <= 0) return false;
    done += static_cast<size_t>(n);
  }
  return true;
}

std::string ReadAll(int fd) {
  std::string out;
  char buffer[4096];
  for (ssize_t n; (n = read(fd, buffer, sizeof buffer)) > 0;) out.append(buffer, n);
  return out;
}

/// The operators run in a child process, as real operators do: blocking calls of a few threads
/// starve when they share gRPC's pollers with thousands of busy agent streams in one process,
/// and then the loadgen, not the server, would be measured. Protocol: the child prepares the
/// route and writes 'R' (or 'E'); the parent writes 'G' to start, then closes its end to stop;
/// the child answers with its report as JSON and exits. Forked before any gRPC or thread exists.
class OperatorProcess {
 public:
  bool Start(const fleetnav::loadgen::LoadTarget& server, const OperatorOptions& options) {
    int to_child[2], from_child[2];
    if (pipe(to_child) != 0 || pipe(from_child) != 0) return false;
    pid_ = fork();
    if (pid_ < 0) return false;
    if (pid_ == 0) {
      close(to_child[1]);
      close(from_child[0]);
      _exit(Child(server, options, to_child[0], from_child[1]));
    }
    close(to_child[0]);
    close(from_child[1]);
    to_child_ = to_child[1];
    from_child_ = from_child[0];
    char status = 'E';
    return read(from_child_, &status, 1) == 1 && status == 'R';
  }
  void Go() { (void)WriteAll(to_child_, "G"); }
  OperatorReport Stop() {
    close(to_child_);
    const std::string text = ReadAll(from_child_);
    close(from_child_);
    int status = 0;
    waitpid(pid_, &status, 0);
    OperatorReport report;
    nlohmann::json json = nlohmann::json::parse(text, nullptr, false);
    if (json.is_discarded() || !json.is_object()) return report;
    report.submit_ms = json.value("submit_ms", std::vector<double>{});
    report.dispatch_ms = json.value("dispatch_ms", std::vector<double>{});
    report.big_submit_ms = json.value("big_submit_ms", std::vector<double>{});
    report.submit_errors = json.value("submit_errors", uint64_t{0});
    report.watches = json.value("watches", uint64_t{0});
    return report;
  }

 private:
  static int Child(const fleetnav::loadgen::LoadTarget& server, const OperatorOptions& options,
                   int in, int out) {
    auto control = v1::FleetService::NewStub(NewChannel(server, -1));
    if (!PrepareRoute(control.get(), options.site)) {
      (void)WriteAll(out, "E");
      return 1;
    }
    (void)WriteAll(out, "R");
    char go = 0;
    if (read(in, &go, 1) != 1) return 0;
    std::atomic<bool> stop{false};
    std::thread stopper([&] {
      (void)ReadAll(in);  // end of file: the parent closed its end
      stop.store(true);
    });
    OperatorReport report = RunOperators(server, options, stop);
    stopper.join();
    const nlohmann::json json = {{"submit_ms", report.submit_ms},
                                 {"dispatch_ms", report.dispatch_ms},
                                 {"big_submit_ms", report.big_submit_ms},
                                 {"submit_errors", report.submit_errors},
                                 {"watches", report.watches}};
    return WriteAll(out, json.dump()) ? 0 : 1;
  }

  pid_t pid_ = -1;
  int to_child_ = -1;
  int from_child_ = -1;
};

/// Idle WatchJob streams on one job that stays queued (its route has a turn, which no loadgen
/// agent advertises) and as many idle WatchFleet streams, 100 to a connection, each read up to its
/// first message and then left open until the run ends.
class IdleWatchers {
 public:
  void Open(const fleetnav::loadgen::LoadTarget& server, int count) {
    auto control = v1::FleetService::NewStub(NewChannel(server, -2));
    grpc::ClientContext submit_context;
    v1::SubmitJobRequest submit;
    submit.set_route_name("loadgen-idle");
    v1::SubmitJobResponse job;
    if (!control->SubmitJob(&submit_context, submit, &job).ok()) return;
    for (int i = 0; i < 2 * count; ++i) {
      if (i % 100 == 0) stubs_.push_back(v1::FleetService::NewStub(NewChannel(server, 3000 + i)));
      auto stream = std::make_unique<Stream>();
      if (i % 2 == 0) {
        v1::WatchJobRequest request;
        request.set_job_id(job.job().job_id());
        stream->job = stubs_.back()->WatchJob(&stream->context, request);
        v1::JobEvent first;
        open_ += stream->job->Read(&first);
      } else {
        stream->fleet = stubs_.back()->WatchFleet(&stream->context, v1::WatchFleetRequest());
        v1::FleetUpdate first;
        open_ += stream->fleet->Read(&first);
      }
      streams_.push_back(std::move(stream));
    }
  }
  int open() const { return open_; }
  ~IdleWatchers() {
    for (auto& stream : streams_) stream->context.TryCancel();
    for (auto& stream : streams_) {
      if (stream->job) (void)stream->job->Finish();
      if (stream->fleet) (void)stream->fleet->Finish();
    }
  }

 private:
  struct Stream {
    grpc::ClientContext context;
    std::unique_ptr<grpc::ClientReader<v1::JobEvent>> job;
    std::unique_ptr<grpc::ClientReader<v1::FleetUpdate>> fleet;
  };
  std::vector<std::unique_ptr<v1::FleetService::Stub>> stubs_;
  std::vector<std::unique_ptr<Stream>> streams_;
  int open_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  std::string server = "127.0.0.1:50051", tls_dir;
  int agents = 100, submitters = 2, threads = 2, streams_per_connection = 250;
  double rate_hz = 10.0, duration_s = 10.0, submit_rate_hz = 20.0;
  pid_t server_pid = 0;
  bool json = false;
  int capable_agents = 0, idle_watchers = 0;
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
  CLI11_PARSE(app, argc, argv);
  // Debian's abseil checks lock order on every absl::Mutex use (gRPC's too): measure without.
  absl::SetMutexDeadlockDetectionMode(absl::OnDeadlockCycle::kIgnore);
  if (agents < 0 || submitters < 0 || !(rate_hz > 0) || !(duration_s > 0) || threads < 1 ||
      streams_per_connection < 1 || capable_agents < 0 || idle_watchers < 0 ||
      operator_options.watch_every < 1 || operator_options.site.big_map_mb < 0 ||
      (idle_watchers > 0 && submitters == 0)) {
    std::cerr << "fleetnav-loadgen: --agents/--submitters must be >= 0, rates and duration > 0, "
                 "--threads and --streams-per-connection >= 1, --watch-every >= 1; "
                 "--idle-watchers needs a submitter (the operators prepare the site)\n";
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
  if (worker_count == 0) {
    std::this_thread::sleep_until(std::chrono::steady_clock::now() +
                                  std::chrono::nanoseconds(run_start_ns - SteadyNowNs()) +
                                  std::chrono::duration<double>(duration_s));
  }
  while (reported_workers.load() < worker_count) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  const double elapsed_s = (SteadyNowNs() - run_start_ns) * 1e-9;
  const double cpu_end = server_pid > 0 ? fleetnav::loadgen::ProcessCpuSeconds(server_pid) : -1;
  const double rss_mb = server_pid > 0 ? fleetnav::loadgen::ProcessRssMb(server_pid) : -1;
  const OperatorReport submit = submitters > 0 ? operators.Stop() : OperatorReport{};
  release.store(true);
  for (std::thread& t : worker_threads) t.join();
  workers.clear();
  uint64_t delivered = 0, skipped = 0, scheduled = 0;
  std::vector<double> latencies;
  for (fleetnav::loadgen::WorkerReport& report : reports) {
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
  std::cout << out.dump() << std::endl;
  return 0;
}
