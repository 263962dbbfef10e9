#include "fleetnav/scenario/scenario_runner.hpp"

#include <grpcpp/grpcpp.h>
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <thread>

#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "absl/strings/strip.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/clock.hpp"
#include "fleetnav/proto/channel_credentials.hpp"
#include "fleetnav/proto/geometry_convert.hpp"
#include "fleetnav/proto/server_target.hpp"
#include "fleetnav/scenario/child_process.hpp"
#include "fleetnav/scenario/link_proxy.hpp"
#include "fleetnav/v1/fleet_service.grpc.pb.h"
#include "fleetnav/v1/sim_service.grpc.pb.h"

namespace fleetnav::scenario {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// fleetnavd's exit line "N assigning dispatch passes, p50 X ms, p99 Y ms, max Z ms; M one-job
/// passes, p50 A ms, p99 B ms, max C ms; one-job pass CPU p50 D ms, p99 E ms, max F ms".
void ReadAssigningPasses(const std::string& log, ScenarioReport* report) {
  const size_t at = log.rfind(" assigning dispatch passes, ");
  if (at == std::string::npos) return;
  const size_t line = log.rfind(' ', at - 1);
  long long count = 0;
  double p50 = 0.0, p99 = 0.0, max = 0.0;
  if (std::sscanf(log.c_str() + line + 1,
                  "%lld assigning dispatch passes, p50 %lf ms, p99 %lf ms, max %lf ms", &count,
                  &p50, &p99, &max) == 4) {
    report->assigning_passes = count;
    report->assigning_pass_ms_p50 = p50;
    report->assigning_pass_ms_p99 = p99;
    report->assigning_pass_ms_max = max;
  }
  const size_t one = log.find(" one-job passes, ", at);
  if (one == std::string::npos) return;
  const size_t one_line = log.rfind(' ', one - 1);
  if (std::sscanf(log.c_str() + one_line + 1,
                  "%lld one-job passes, p50 %lf ms, p99 %lf ms, max %lf ms", &count, &p50, &p99,
                  &max) == 4) {
    report->one_job_passes = count;
    report->one_job_pass_ms_p50 = p50;
    report->one_job_pass_ms_p99 = p99;
    report->one_job_pass_ms_max = max;
  }
  const size_t cpu = log.find("one-job pass CPU ", one);
  if (cpu != std::string::npos &&
      std::sscanf(log.c_str() + cpu, "one-job pass CPU p50 %lf ms, p99 %lf ms, max %lf ms", &p50,
                  &p99, &max) == 3) {
    report->one_job_pass_cpu_ms_p50 = p50;
    report->one_job_pass_cpu_ms_p99 = p99;
    report->one_job_pass_cpu_ms_max = max;
  }
}

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string StateName(v1::JobState state) {
  std::string name = v1::JobState_Name(state);
  absl::AsciiStrToLower(&name);
  return name.rfind("job_state_", 0) == 0 ? name.substr(10) : name;
}

bool IsEnd(const std::string& state) {
  return state == "succeeded" || state == "failed" || state == "cancelled";
}

v1::FaultType SimFaultType(const std::string& name) {
  if (name == "hide_ultrasonic") return v1::FAULT_TYPE_HIDE_ULTRASONIC_REGION;
  if (name == "remove_fence") return v1::FAULT_TYPE_REMOVE_FENCE_SEGMENT;
  if (name == "remove_stripe") return v1::FAULT_TYPE_REMOVE_STRIPE_SEGMENT;
  if (name == "wheel_slip") return v1::FAULT_TYPE_WHEEL_SLIP_REGION;
  if (name == "sensor_dropout") return v1::FAULT_TYPE_SENSOR_DROPOUT;
  if (name == "slow_down") return v1::FAULT_TYPE_SLOW_DOWN;
  return v1::FAULT_TYPE_UNSPECIFIED;
}

void WithDeadline(grpc::ClientContext* context, double seconds = 2.0) {
  context->set_deadline(std::chrono::system_clock::now() +
                        std::chrono::milliseconds(static_cast<int64_t>(seconds * 1000)));
}

/// Rows "robot_id,kind,x,y,t_s" of a trajectory CSV, per robot, in file order.
struct Sample {
  double t_s, x, y;
};
std::map<std::string, std::vector<Sample>> ReadTrajectories(const std::string& path) {
  std::map<std::string, std::vector<Sample>> out;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> f = absl::StrSplit(line, ',');
    if (f.size() < 5) continue;
    try {
      out[f[0]].push_back({std::stod(f[4]), std::stod(f[2]), std::stod(f[3])});
    } catch (const std::exception&) {
      continue;  // a header or a line cut by a kill
    }
  }
  return out;
}

/// One run: the processes, the clients and what has been seen.
class Run {
 public:
  Run(const Scenario& scenario, const Binaries& binaries, const RunOptions& options)
      : s_(scenario), bin_(binaries), opt_(options) {}
  ~Run() {
    for (auto& [id, agent] : agents_) agent.reset();
    sim_.reset();
    servers_.clear();
    if (!keep_ && !work_.empty()) {
      std::error_code ignored;
      fs::remove_all(work_, ignored);
    }
  }

  absl::StatusOr<ScenarioReport> Execute();

 private:
  std::string Path(const std::string& name) const { return (fs::path(work_) / name).string(); }
  absl::Status Ctl(const std::vector<std::string>& args);
  /// With `tls_dev_certs`: the run's development PKI (server, robot and token files).
  absl::Status MakePki();
  bool Tls() const { return !s_.tls_dev_certs.empty(); }
  std::string Pki(const std::string& name) const { return Path("pki/" + name); }
  /// A channel to fleetnavd at `target`: plaintext, or TLS trusting the run's server CA and
  /// sending the admin token with every call.
  std::shared_ptr<grpc::Channel> ServerChannel(const std::string& target) const;
  /// Starts fleetnavd (replica `replica` of s_.replicas) on its port.
  absl::Status StartServer(size_t replica);
  /// fleetnavd's address for clients: one port, or the list of the replicas' ports.
  std::string ServerList() const;
  /// The replica leading the site and its epoch, from the replicas' logs (nullopt: none yet).
  std::optional<std::pair<size_t, int64_t>> Leader() const;
  std::string ServerLog(size_t replica, int start) const {
    return s_.replicas > 1 ? Path(absl::StrCat("fleetnavd-r", replica, ".", start, ".out"))
                           : Path(absl::StrCat("fleetnavd.", start, ".out"));
  }
  absl::Status StartAgent(const ScenarioRobot& robot, const Pose2& pose);
  /// Where fleetnavd last saw the robot (its agent's estimate), else where it was last polled.
  Pose2 LastKnownPose(const ScenarioRobot& robot);
  void Submit(size_t index);
  void Inject(const ScenarioFault& fault);
  void Poll(double sim_s);
  /// The jobs fleetnavd has not ended, by id; false when it did not answer.
  bool ListUnfinishedJobs(std::map<std::string, v1::Job>* jobs);
  /// When an ended job ended, in sim time, from fleetnavd's record of it (held_at_s, the hold
  /// at which it was seen ended, when the record cannot say).
  double EndSimS(const v1::Job& job, double held_at_s) const;
  /// Advances the held simulation to the first tick at or after `sim_s`; returns its sim time
  /// (nullopt when the simulator is gone).
  std::optional<double> RunUntil(double sim_s);
  /// After a start, kill, cut or restore, while the simulation is held: waits until the
  /// simulator and fleetnavd both see it (every running agent attached; with fleetnavd up,
  /// exactly the running agents with a link online), so that the next tick is the same tick in
  /// every run.
  absl::Status Settle(double wall_timeout_s);
  /// Whether fleetnavd serves: no restart of it is pending (with replicas the others serve
  /// while one is down).
  bool ServerUp() const {
    return s_.replicas > 1 || std::none_of(restarts_.begin(), restarts_.end(),
                                           [](const Restart& r) { return r.robot_id.empty(); });
  }
  void DrawProgress(double sim_s);
  void Finish(ScenarioReport* report);
  int RobotIndex(const std::string& robot_id) const {
    for (size_t i = 0; i < s_.robots.size(); ++i) {
      if (s_.robots[i].robot_id == robot_id) return static_cast<int>(i);
    }
    return 0;
  }

  const Scenario& s_;
  const Binaries& bin_;
  const RunOptions& opt_;
  unsigned seed_ = 1;
  bool keep_ = false;
  std::string work_;
  /// fleetnavd, or each replica of it: the process, its port (kept across restarts) and how
  /// often it was started.
  struct ServerProcess {
    std::unique_ptr<ChildProcess> process;
    int port = 0;
    int starts = 0;
  };
  std::vector<ServerProcess> servers_;
  std::string admin_token_;  ///< with TLS: what the runner and fleetnavctl show
  int sim_port_ = 0;
  /// A leader killed whose successor has not been seen yet.
  struct PendingFailover {
    Clock::time_point killed;
    int64_t epoch = 0;
  };
  std::optional<PendingFailover> failover_;
  std::vector<double> failovers_s_;  ///< wall time from each leader kill to its successor
  std::unique_ptr<ChildProcess> sim_;
  std::map<std::string, std::unique_ptr<ChildProcess>> agents_;
  /// CPU time of processes already ended (killed by a fault).
  double server_cpu_s_ = 0.0;
  double agents_cpu_s_ = 0.0;
  /// The links of the robots a cut_link fault names go through a proxy.
  std::map<std::string, std::unique_ptr<LinkProxy>> links_;
  struct LinkRestore {
    double sim_s;
    std::string robot_id;
  };
  std::vector<LinkRestore> link_restores_;
  std::map<std::string, int> agent_starts_;
  std::unique_ptr<v1::FleetService::Stub> fleet_;
  std::unique_ptr<v1::SimService::Stub> simulator_;
  std::vector<JobOutcome> jobs_;
  std::vector<bool> submitted_;
  std::vector<double> progress_;
  std::vector<bool> injected_;
  std::map<std::string, RobotFigures> figures_;
  std::map<std::string, std::string> waits_;
  std::map<std::string, Pose2> estimates_;
  /// The simulation's calendar at sim time 0 (fleetnav-sim --start-unix-ms).
  int64_t sim_start_unix_ms_ = 0;
  /// Each robot's traffic_held_s at the last poll.
  std::map<std::string, double> held_seen_s_;
  int drawn_lines_ = 0;
  struct Restart {
    double due_sim_s = 0.0;
    std::string robot_id;  ///< empty: the server replica below
    size_t replica = 0;
  };
  std::vector<Restart> restarts_;
};

/// The name the development server certificate carries (make-dev-certs' default names): a
/// list of replicas is no name a certificate can match, so TLS clients are told it.
constexpr char kDevServerName[] = "localhost";

absl::Status Run::MakePki() {
  std::vector<std::string> argv{s_.tls_dev_certs, Path("pki")};
  for (const ScenarioRobot& robot : s_.robots) argv.push_back(robot.robot_id);
  ChildProcess pki(argv, Path("pki.out"), Path("pki.err"));
  if (pki.Wait(120.0) != 0) {
    return absl::InternalError(
        absl::StrCat(s_.tls_dev_certs, " did not make the run's PKI: ", pki.Stderr()));
  }
  admin_token_ = std::string(absl::StripAsciiWhitespace(ReadWholeFile(Pki("admin.token"))));
  if (admin_token_.empty()) return absl::InternalError("the run's PKI holds no admin token");
  return absl::OkStatus();
}

std::shared_ptr<grpc::Channel> Run::ServerChannel(const std::string& target) const {
  if (!Tls()) return grpc::CreateChannel(target, grpc::InsecureChannelCredentials());
  ClientTlsFiles files;
  files.ca_path = Pki("server-ca.crt");
  files.server_name = kDevServerName;
  absl::StatusOr<std::shared_ptr<grpc::ChannelCredentials>> tls = MakeChannelCredentials(files);
  grpc::ChannelArguments arguments;
  AddTlsChannelArguments(files, &arguments);
  // MakePki checked the files; should they have gone, every call fails UNAVAILABLE and says so.
  return grpc::CreateCustomChannel(
      target,
      grpc::CompositeChannelCredentials(tls.ok() ? *tls : grpc::SslCredentials({}),
                                        grpc::AccessTokenCredentials(admin_token_)),
      arguments);
}

absl::Status Run::Ctl(const std::vector<std::string>& args) {
  std::vector<std::string> argv{bin_.ctl, "--server", ServerList()};
  if (Tls()) {
    argv.insert(argv.end(), {"--tls-ca", Pki("server-ca.crt"), "--tls-server-name", kDevServerName,
                             "--token", admin_token_});
  }
  argv.insert(argv.end(), args.begin(), args.end());
  ChildProcess ctl(argv, Path("ctl.out"), Path("ctl.err"));
  const std::optional<int> code = ctl.Wait(120.0);
  if (!code || *code != 0) {
    return absl::InternalError(
        absl::StrCat("fleetnavctl ", args.front(), " ", args.at(1), " failed: ", ctl.Stderr()));
  }
  return absl::OkStatus();
}

std::string Run::ServerList() const {
  // The replicas' list, as an operator gives it to the agents and fleetnavctl: a client takes
  // the first replica that answers, the next when it dies.
  std::vector<std::string> addresses;
  for (const ServerProcess& server : servers_) {
    addresses.push_back(absl::StrCat("127.0.0.1:", server.port));
  }
  return absl::StrJoin(addresses, ",");
}

std::optional<std::pair<size_t, int64_t>> Run::Leader() const {
  std::optional<std::pair<size_t, int64_t>> leader;
  for (size_t i = 0; i < servers_.size(); ++i) {
    if (servers_[i].process == nullptr || !servers_[i].process->running()) continue;
    // fleetnavd's line when it leads (docs/server.md): "... leading at epoch N (...".
    const std::string log = ReadWholeFile(ServerLog(i, servers_[i].starts));
    static constexpr std::string_view kLeading = "leading at epoch ";
    for (size_t at = log.find(kLeading); at != std::string::npos; at = log.find(kLeading, at + 1)) {
      const int64_t epoch = std::strtoll(log.c_str() + at + kLeading.size(), nullptr, 10);
      if (!leader || epoch > leader->second) leader = std::make_pair(i, epoch);
    }
  }
  return leader;
}

absl::Status Run::StartServer(size_t replica) {
  ServerProcess& server = servers_[replica];
  const std::string port_file = Path(absl::StrCat("server", replica, ".port"));
  fs::remove(port_file);
  ++server.starts;
  std::vector<std::string> argv{
      bin_.server, "--listen", absl::StrCat("127.0.0.1:", server.port), "--port-file", port_file,
      "--db", opt_.db.empty() ? Path("fleet.db") : opt_.db,
      // fleetnavd counts the simulator's time, tick by tick with its agents (the lockstep).
      "--clock", "sim", "--sim", absl::StrCat("127.0.0.1:", sim_port_)};
  if (Tls()) {
    argv.insert(argv.end(),
                {"--tls-cert", Pki("server.crt"), "--tls-key", Pki("server.key"), "--tls-client-ca",
                 Pki("robot-ca.crt"), "--tokens", Pki("tokens.yaml")});
  } else {
    argv.push_back("--insecure");
  }
  if (s_.replicas > 1) argv.push_back("--replica");
  server.process = std::make_unique<ChildProcess>(
      argv, ServerLog(replica, server.starts),
      Path(absl::StrCat(s_.replicas > 1 ? absl::StrCat("fleetnavd-r", replica) : "fleetnavd", ".",
                        server.starts, ".log")));
  const int port = WaitForPortFile(port_file);
  if (!server.process->started() || port == 0) {
    return absl::UnavailableError(
        absl::StrCat("fleetnavd did not start: ", server.process->Stderr()));
  }
  server.port = port;
  return absl::OkStatus();
}

/// `command` run under nice(1) with `niceness` (itself when 0): nice execs the program with the
/// lower priority, so all its threads inherit it.
std::vector<std::string> Niced(int niceness, const std::vector<std::string>& command) {
  if (niceness <= 0) return command;
  std::vector<std::string> niced = {"/usr/bin/nice", "-n", absl::StrCat(niceness)};
  niced.insert(niced.end(), command.begin(), command.end());
  return niced;
}

absl::Status Run::StartAgent(const ScenarioRobot& robot, const Pose2& pose) {
  const int start = ++agent_starts_[robot.robot_id];
  const auto link = links_.find(robot.robot_id);
  const std::string server =
      link != links_.end() ? absl::StrCat("127.0.0.1:", link->second->port()) : ServerList();
  const std::string stem = absl::StrCat("agent-", robot.robot_id, ".", start);
  std::vector<std::string> argv{bin_.agent,
                                "--robot-id",
                                robot.robot_id,
                                "--kind",
                                robot.kind_name,
                                "--sim",
                                absl::StrCat("127.0.0.1:", sim_port_),
                                "--server",
                                server,
                                "--initial-pose",
                                absl::StrFormat("%.4f", pose.x_m()),
                                absl::StrFormat("%.4f", pose.y_m()),
                                absl::StrFormat("%.3f", RadToDeg(pose.yaw_rad())),
                                "--particles",
                                absl::StrCat(robot.particles),
                                "--seed",
                                absl::StrCat(seed_ + 1000 * start + RobotIndex(robot.robot_id)),
                                "--record",
                                Path(absl::StrCat("estimate-", robot.robot_id, ".csv"))};
  if (Tls()) {
    // The robot's own certificate: its common name is its id.
    argv.insert(argv.end(), {"--tls-ca", Pki("server-ca.crt"), "--tls-cert",
                             Pki(absl::StrCat("robot-", robot.robot_id, ".crt")), "--tls-key",
                             Pki(absl::StrCat("robot-", robot.robot_id, ".key")),
                             "--tls-server-name", kDevServerName});
  }
  agents_[robot.robot_id] = std::make_unique<ChildProcess>(
      Niced(opt_.agent_niceness, argv), Path(stem + ".out"), Path(stem + ".log"));
  if (!agents_[robot.robot_id]->started()) {
    return absl::UnavailableError(
        absl::StrCat("fleetnav-agent for ", robot.robot_id, " did not start"));
  }
  return absl::OkStatus();
}

Pose2 Run::LastKnownPose(const ScenarioRobot& robot) {
  // Asked now, not taken from the last poll: the robot has moved since.
  grpc::ClientContext context;
  WithDeadline(&context);
  v1::GetRobotRequest request;
  request.set_robot_id(robot.robot_id);
  v1::GetRobotResponse response;
  if (fleet_->GetRobot(&context, request, &response).ok() &&
      response.robot().has_last_telemetry()) {
    absl::StatusOr<Pose2> pose =
        fleetnav::FromProto(response.robot().last_telemetry().pose_in_map().pose());
    if (pose.ok()) return *pose;
  }
  const auto polled = estimates_.find(robot.robot_id);
  return polled != estimates_.end() ? polled->second : robot.initial_pose;
}

void Run::Submit(size_t index) {
  const ScenarioJob& job = s_.jobs[index];
  v1::SubmitJobRequest request;
  if (job.goal) {
    request.mutable_goal()->set_map_id(s_.map_id);
    *request.mutable_goal()->mutable_goal() = fleetnav::ToProto(*job.goal);
  } else {
    request.set_route_name(job.route);
  }
  request.set_robot_id(job.robot_id);
  request.set_priority(job.priority);
  // Submitting again after a server restart names the same job.
  request.set_idempotency_key(absl::StrCat("scenario/", s_.name, "/", job.name));
  grpc::ClientContext context;
  WithDeadline(&context);
  v1::SubmitJobResponse response;
  const grpc::Status status = fleet_->SubmitJob(&context, request, &response);
  if (!status.ok()) {
    if (status.error_code() != grpc::StatusCode::UNAVAILABLE &&
        status.error_code() != grpc::StatusCode::DEADLINE_EXCEEDED) {
      jobs_[index].state = "failed";
      jobs_[index].reason = absl::StrCat("refused by fleetnavd: ", status.error_message());
      submitted_[index] = true;
    }
    return;  // retried on the next poll while the server is away
  }
  jobs_[index].job_id = response.job().job_id();
  jobs_[index].state = StateName(response.job().state());
  submitted_[index] = true;
}

void Run::Inject(const ScenarioFault& fault) {
  switch (fault.type) {
    case ScenarioFaultType::kKillAgent:
      if (auto it = agents_.find(fault.robot_id); it != agents_.end()) {
        it->second->Stop(SIGKILL, 5.0);
        agents_cpu_s_ += it->second->cpu_s().value_or(0.0);
        restarts_.push_back({fault.at_s + fault.restart_after_s, fault.robot_id});
      }
      return;
    case ScenarioFaultType::kKillServer:
    case ScenarioFaultType::kKillLeader: {
      size_t replica = 0;
      if (fault.type == ScenarioFaultType::kKillLeader) {
        const std::optional<std::pair<size_t, int64_t>> leader = Leader();
        if (!leader) return;  // none yet: nothing to kill
        replica = leader->first;
        failover_ = PendingFailover{Clock::now(), leader->second};
      }
      ServerProcess& server = servers_[replica];
      server.process->Stop(SIGKILL, 5.0);
      server_cpu_s_ += server.process->cpu_s().value_or(0.0);
      // The registry that counted the time robots stood held is gone: the next one (the server
      // started again, or the replica that takes the site over) counts from zero.
      held_seen_s_.clear();
      restarts_.push_back({fault.at_s + fault.restart_after_s, "", replica});
      return;
    }
    case ScenarioFaultType::kCutLink:
      if (auto it = links_.find(fault.robot_id); it != links_.end()) {
        it->second->Cut();
        link_restores_.push_back({fault.at_s + fault.duration_s, fault.robot_id});
      }
      return;
    case ScenarioFaultType::kSimFault: {
      v1::InjectFaultRequest request;
      request.set_type(SimFaultType(fault.sim_type));
      request.set_robot_id(fault.robot_id);
      request.set_sensor_name(fault.sensor);
      request.set_duration_s(fault.duration_s);
      request.set_factor(fault.factor);
      if (fault.region) {
        request.mutable_region_min()->set_x_m(fault.region->first.x_m());
        request.mutable_region_min()->set_y_m(fault.region->first.y_m());
        request.mutable_region_max()->set_x_m(fault.region->second.x_m());
        request.mutable_region_max()->set_y_m(fault.region->second.y_m());
      }
      grpc::ClientContext context;
      WithDeadline(&context);
      v1::InjectFaultResponse response;
      (void)simulator_->InjectFault(&context, request, &response);
      return;
    }
  }
}

void Run::Poll(double sim_s) {
  {
    grpc::ClientContext context;
    WithDeadline(&context);
    v1::ListRobotsResponse robots;
    if (fleet_->ListRobots(&context, v1::ListRobotsRequest{}, &robots).ok()) {
      for (const v1::RobotState& robot : robots.robots()) {
        waits_[robot.robot_id()] = robot.traffic_wait();
        RobotFigures& f = figures_[robot.robot_id()];
        // fleetnavd sums, in sim time, how long each robot stood held (exact between holds).
        // A fleetnavd that started again (or a replica that took over) counts from zero: the
        // runner forgets what it saw when it kills one, and a count that fell is a new one.
        double& seen_s = held_seen_s_[robot.robot_id()];
        const double held_s = robot.traffic_held_s();
        f.waiting_s += held_s >= seen_s ? held_s - seen_s : held_s;
        seen_s = held_s;
        // Held means standing: a robot still driving the actions it was cleared for is not.
        const bool standing = robot.last_telemetry().mode() == v1::NAVIGATION_MODE_IDLE;
        if (!robot.traffic_wait().empty() && standing &&
            std::find(f.waits.begin(), f.waits.end(), robot.traffic_wait()) == f.waits.end()) {
          f.waits.push_back(robot.traffic_wait());
        }
        absl::StatusOr<Pose2> pose =
            fleetnav::FromProto(robot.last_telemetry().pose_in_map().pose());
        if (pose.ok()) estimates_[robot.robot_id()] = *pose;
      }
    }
  }
  // One listing of the unfinished jobs per hold: a GetJob per job would be most of the run's
  // messages with dozens of jobs. A job no longer listed has ended and is read once more.
  std::map<std::string, v1::Job> unfinished;
  if (!ListUnfinishedJobs(&unfinished)) return;  // the server did not answer: the next hold
  for (size_t i = 0; i < jobs_.size(); ++i) {
    if (!submitted_[i] || jobs_[i].job_id.empty() || IsEnd(jobs_[i].state)) continue;
    v1::Job job;
    if (auto listed = unfinished.find(jobs_[i].job_id); listed != unfinished.end()) {
      job = std::move(listed->second);
    } else {
      grpc::ClientContext context;
      WithDeadline(&context);
      v1::GetJobRequest request;
      request.set_job_id(jobs_[i].job_id);
      v1::GetJobResponse response;
      if (!fleet_->GetJob(&context, request, &response).ok()) continue;
      job = std::move(*response.mutable_job());
    }
    const std::string state = StateName(job.state());
    jobs_[i].robot_id = job.assigned_robot_id();
    jobs_[i].reason = job.reason();
    if (state != jobs_[i].state && opt_.progress != nullptr && !opt_.progress_is_terminal) {
      *opt_.progress << absl::StrFormat("t=%7.1f s  %-16s %-8s %s%s\n", sim_s, jobs_[i].name,
                                        jobs_[i].robot_id, state,
                                        jobs_[i].reason.empty() ? "" : ": " + jobs_[i].reason);
    }
    jobs_[i].state = state;
    progress_[i] = job.progress_fraction();
    if (IsEnd(state)) jobs_[i].end_sim_s = EndSimS(job, sim_s);
  }
}

double Run::EndSimS(const v1::Job& job, double held_at_s) const {
  // fleetnavd stamps on the simulation's calendar: the record says at which tick it ended.
  if (job.updated_unix_ms() < sim_start_unix_ms_) return held_at_s;
  return std::min(held_at_s,
                  static_cast<double>(job.updated_unix_ms() - sim_start_unix_ms_) * 1e-3);
}

bool Run::ListUnfinishedJobs(std::map<std::string, v1::Job>* jobs) {
  v1::ListJobsRequest request;
  for (const v1::JobState state : {v1::JOB_STATE_QUEUED, v1::JOB_STATE_ASSIGNED,
                                   v1::JOB_STATE_RUNNING, v1::JOB_STATE_PAUSED}) {
    request.add_states(state);
  }
  request.set_page_size(1000);
  do {
    grpc::ClientContext context;
    WithDeadline(&context);
    v1::ListJobsResponse response;
    if (!fleet_->ListJobs(&context, request, &response).ok()) return false;
    for (v1::Job& job : *response.mutable_jobs()) {
      const std::string id = job.job_id();
      (*jobs)[id] = std::move(job);
    }
    request.set_page_token(response.next_page_token());
  } while (!request.page_token().empty());
  return true;
}

std::optional<double> Run::RunUntil(double sim_s) {
  grpc::ClientContext context;
  // No deadline of its own: a slow machine makes the run slower, never different.
  WithDeadline(&context, std::max(1.0, opt_.wall_timeout_s));
  v1::RunUntilRequest request;
  request.set_sim_time_ns(std::llround(sim_s * 1e9));
  v1::RunResponse response;
  if (!simulator_->RunUntil(&context, request, &response).ok()) return std::nullopt;
  return static_cast<double>(response.sim_time_ns()) * 1e-9;
}

absl::Status Run::Settle(double wall_timeout_s) {
  const Clock::time_point give_up =
      Clock::now() + std::chrono::milliseconds(static_cast<int64_t>(wall_timeout_s * 1000));
  const bool server_up = ServerUp();
  std::string missing;
  while (Clock::now() < give_up) {
    missing.clear();
    std::set<std::string> attached;
    {
      grpc::ClientContext context;
      WithDeadline(&context);
      v1::GetWorldResponse world;
      if (simulator_->GetWorld(&context, v1::GetWorldRequest{}, &world).ok()) {
        for (const v1::SimRobotInfo& robot : world.robots()) {
          if (robot.attached()) attached.insert(robot.robot_id());
        }
      }
    }
    std::set<std::string> online;
    if (server_up) {
      grpc::ClientContext context;
      WithDeadline(&context);
      v1::ListRobotsResponse robots;
      if (fleet_->ListRobots(&context, v1::ListRobotsRequest{}, &robots).ok()) {
        for (const v1::RobotState& r : robots.robots()) {
          if (r.connection() == v1::CONNECTION_STATE_ONLINE) online.insert(r.robot_id());
        }
      } else {
        missing = "fleetnavd's robots";
      }
    }
    for (const auto& [id, agent] : agents_) {
      const bool running = agent != nullptr && agent->running();
      const auto link = links_.find(id);
      const bool linked = running && (link == links_.end() || !link->second->cut());
      if (running && !attached.contains(id)) absl::StrAppend(&missing, " ", id, " attached");
      if (server_up && linked != online.contains(id)) {
        absl::StrAppend(&missing, " ", id, linked ? " online" : " offline");
      }
    }
    if (missing.empty()) return absl::OkStatus();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return absl::DeadlineExceededError(
      absl::StrCat("the simulator and fleetnavd did not settle within ", wall_timeout_s,
                   " s: waiting for", missing));
}

void Run::DrawProgress(double sim_s) {
  if (opt_.progress == nullptr || !opt_.progress_is_terminal) return;
  std::ostream& out = *opt_.progress;
  if (drawn_lines_ > 0) out << "\033[" << drawn_lines_ << "A";
  drawn_lines_ = 0;
  out << absl::StrFormat("\033[2K%s  sim %.1f s\n", s_.name, sim_s);
  ++drawn_lines_;
  for (size_t i = 0; i < jobs_.size(); ++i) {
    const int filled = static_cast<int>(std::lround(std::clamp(progress_[i], 0.0, 1.0) * 30));
    const std::string bar = std::string(filled, '#') + std::string(30 - filled, '.');
    const std::string wait = waits_[jobs_[i].robot_id];
    out << absl::StrFormat("\033[2K%-16s %-8s [%s] %3d%%  %-10s %s\n", jobs_[i].name,
                           jobs_[i].robot_id, bar, static_cast<int>(progress_[i] * 100),
                           submitted_[i] ? jobs_[i].state : "waiting",
                           IsEnd(jobs_[i].state) ? jobs_[i].reason : wait);
    ++drawn_lines_;
  }
  out.flush();
}

absl::StatusOr<ScenarioReport> Run::Execute() {
  const Clock::time_point wall_start = Clock::now();
  seed_ = opt_.seed.value_or(s_.seed);
  keep_ = !opt_.keep_dir.empty();
  if (keep_) {
    work_ = opt_.keep_dir;
    fs::create_directories(work_);
    // A folder kept from an earlier run: the database, the recordings and the logs start
    // fresh all the same (the recordings are appended to, and would mix two runs).
    std::error_code ignored;
    for (const fs::directory_entry& entry : fs::directory_iterator(work_, ignored)) {
      const std::string name = entry.path().filename().string();
      const std::string ext = entry.path().extension().string();
      if (entry.is_regular_file() && (absl::StartsWith(name, "fleet.db") || name == "truth.csv" ||
                                      absl::StartsWith(name, "estimate-") || ext == ".log" ||
                                      ext == ".out" || ext == ".err" || ext == ".port")) {
        fs::remove(entry.path(), ignored);
      }
    }
  } else {
    char pattern[] = "/tmp/fleetnav-scenario.XXXXXX";
    if (mkdtemp(pattern) == nullptr) return absl::InternalError("cannot make a temporary folder");
    work_ = pattern;
  }
  jobs_.resize(s_.jobs.size());
  submitted_.assign(s_.jobs.size(), false);
  progress_.assign(s_.jobs.size(), 0.0);
  injected_.assign(s_.faults.size(), false);
  for (size_t i = 0; i < s_.jobs.size(); ++i) {
    jobs_[i].name = s_.jobs[i].name;
    jobs_[i].robot_id = s_.jobs[i].robot_id;
    jobs_[i].state = "waiting";
    const auto expected = s_.expect.job_states.find(s_.jobs[i].name);
    jobs_[i].expected =
        expected != s_.expect.job_states.end() ? expected->second : s_.expect.all_jobs;
  }
  for (const ScenarioRobot& robot : s_.robots) figures_[robot.robot_id].robot_id = robot.robot_id;

  // The world's map and markers, as an operator would export them.
  {
    ChildProcess exporter({bin_.sim, "--world", s_.world_path, "--export-map", Path("map")},
                          Path("export.out"), Path("export.log"));
    if (exporter.Wait(120.0) != 0) {
      return absl::InternalError(absl::StrCat("map export failed: ", exporter.Stderr()));
    }
  }
  // The simulation's calendar starts now; fleetnavd stamps its records from it.
  sim_start_unix_ms_ = fleetnav::SystemClock().UnixMs();
  const std::string sim_port_file = Path("sim.port");
  fs::remove(sim_port_file);  // a kept folder's port file names a simulator long gone
  sim_ = std::make_unique<ChildProcess>(
      Niced(opt_.sim_niceness,
            {bin_.sim, "--world", s_.world_path, "--listen", "127.0.0.1:0", "--port-file",
             sim_port_file, "--seed", absl::StrCat(seed_), "--real-time-factor",
             absl::StrCat(s_.real_time_factor), "--start-unix-ms", absl::StrCat(sim_start_unix_ms_),
             "--hold", "--record-truth", Path("truth.csv")}),
      Path("sim.out"), Path("sim.log"));
  sim_port_ = WaitForPortFile(sim_port_file);
  if (!sim_->started() || sim_port_ == 0) {
    return absl::UnavailableError(absl::StrCat("fleetnav-sim did not start: ", sim_->Stderr()));
  }
  simulator_ = v1::SimService::NewStub(grpc::CreateChannel(absl::StrCat("127.0.0.1:", sim_port_),
                                                           grpc::InsecureChannelCredentials()));
  if (Tls()) {
    if (absl::Status st = MakePki(); !st.ok()) return st;
  }
  // fleetnavd counts the simulator's time: its timeouts then hold at any speed.
  servers_.resize(static_cast<size_t>(s_.replicas));
  // Replicas on the default SQLite file: fleetnavd refuses them, naming why.
  for (size_t replica = 0; replica < servers_.size(); ++replica) {
    if (absl::Status st = StartServer(replica); !st.ok()) return st;
  }
  // Every replica answers once it knows the leader.
  for (const ServerProcess& server : servers_) {
    auto stub = v1::FleetService::NewStub(ServerChannel(absl::StrCat("127.0.0.1:", server.port)));
    for (int tries = 0;; ++tries) {
      grpc::ClientContext context;
      WithDeadline(&context);
      v1::ListRobotsResponse robots;
      if (stub->ListRobots(&context, v1::ListRobotsRequest{}, &robots).ok()) break;
      if (tries == 300) {
        return absl::UnavailableError(
            absl::StrCat("fleetnavd on port ", server.port, " did not answer within 30 s"));
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  }
  fleet_ = v1::FleetService::NewStub(ServerChannel(fleetnav::ServerTarget(ServerList()).value()));
  const std::string map_yaml = Path(absl::StrCat("map/", s_.map_id, ".yaml"));
  const std::string markers_yaml = Path(absl::StrCat("map/", s_.map_id, ".markers.yaml"));
  if (absl::Status st = Ctl({"map", "import", "--id", s_.map_id, map_yaml}); !st.ok()) return st;
  if (fs::exists(markers_yaml)) {
    if (absl::Status st = Ctl({"markers", "put", markers_yaml}); !st.ok()) return st;
  }
  for (const std::string& route : s_.route_paths) {
    if (absl::Status st = Ctl({"routes", "put", route}); !st.ok()) return st;
  }
  for (const ScenarioFault& fault : s_.faults) {
    if (fault.type != ScenarioFaultType::kCutLink || links_.contains(fault.robot_id)) continue;
    absl::StatusOr<std::unique_ptr<LinkProxy>> proxy = LinkProxy::Start(servers_[0].port);
    if (!proxy.ok()) return proxy.status();
    links_[fault.robot_id] = *std::move(proxy);
  }
  for (const ScenarioRobot& robot : s_.robots) {
    if (absl::Status st = StartAgent(robot, robot.initial_pose); !st.ok()) return st;
  }
  // Jobs name robots: submit once every agent has said hello (and is in the simulator's
  // barrier), while the simulation is still held at tick 0.
  if (absl::Status settled = Settle(60.0); !settled.ok()) {
    return absl::DeadlineExceededError(
        absl::StrCat("the agents did not all connect: ", settled.message()));
  }

  // The simulation advances only as far as the runner asks (RunUntil), and everything the
  // runner does — submitting, injecting, restarting, polling — happens while it is held at an
  // exact tick: with the lockstep of agents and fleetnavd, a seed gives the same run every time.
  // Holds cost a drained pipeline each (agents, fleetnavd and the simulator all wait for the
  // runner), so the runner holds once a sim second besides its events: what it reports of the
  // time between holds — when jobs ended, how long robots stood held — fleetnavd recorded in
  // sim time.
  constexpr double kPollPeriodS = 1.0;
  double sim_s = 0.0;
  // Whether what is set for `at_s` is due at the held tick (tick times are whole nanoseconds).
  const auto due = [&](double at_s) { return sim_s + 1e-6 >= at_s; };
  while (true) {
    if (SecondsSince(wall_start) > opt_.wall_timeout_s) break;
    bool changed = false;
    // Restarts that are due.
    for (auto it = restarts_.begin(); it != restarts_.end();) {
      if (!due(it->due_sim_s)) {
        ++it;
        continue;
      }
      if (it->robot_id.empty()) {
        if (absl::Status st = StartServer(it->replica); !st.ok()) return st;
      } else {
        for (const ScenarioRobot& robot : s_.robots) {
          if (robot.robot_id != it->robot_id) continue;
          // Restarted where fleetnavd last saw it, as an operator would.
          if (absl::Status st = StartAgent(robot, LastKnownPose(robot)); !st.ok()) return st;
        }
      }
      it = restarts_.erase(it);
      changed = true;
    }
    if (!sim_->running()) break;
    for (auto it = link_restores_.begin(); it != link_restores_.end();) {
      if (!due(it->sim_s)) {
        ++it;
        continue;
      }
      links_.at(it->robot_id)->Restore();
      it = link_restores_.erase(it);
      changed = true;
    }
    for (size_t i = 0; i < s_.faults.size(); ++i) {
      if (!injected_[i] && due(s_.faults[i].at_s)) {
        injected_[i] = true;
        Inject(s_.faults[i]);
        changed = true;
      }
    }
    if (changed) {
      if (absl::Status settled = Settle(120.0); !settled.ok()) return settled;
    }
    const bool server_up = ServerUp();
    if (failover_) {
      const std::optional<std::pair<size_t, int64_t>> leader = Leader();
      if (leader && leader->second > failover_->epoch) {
        failovers_s_.push_back(SecondsSince(failover_->killed));
        failover_.reset();
      }
    }
    if (server_up) {
      for (size_t i = 0; i < s_.jobs.size(); ++i) {
        if (!submitted_[i] && due(s_.jobs[i].at_s)) Submit(i);
      }
      Poll(sim_s);
    }
    DrawProgress(sim_s);
    const bool all_ended =
        std::all_of(jobs_.begin(), jobs_.end(), [](const JobOutcome& j) { return IsEnd(j.state); });
    if (all_ended || sim_s >= s_.expect.deadline_s) break;
    // The next hold: the next poll, or an earlier event.
    double next_s = sim_s + kPollPeriodS;
    const auto earlier = [&](double at_s) {
      if (!due(at_s)) next_s = std::min(next_s, at_s);
    };
    earlier(s_.expect.deadline_s);
    for (const Restart& restart : restarts_) earlier(restart.due_sim_s);
    for (const LinkRestore& restore : link_restores_) earlier(restore.sim_s);
    for (size_t i = 0; i < s_.faults.size(); ++i) {
      if (!injected_[i]) earlier(s_.faults[i].at_s);
    }
    for (size_t i = 0; i < s_.jobs.size(); ++i) {
      if (!submitted_[i]) earlier(s_.jobs[i].at_s);
    }
    const std::optional<double> reached = RunUntil(next_s);
    if (!reached) break;  // the simulator is gone
    sim_s = *reached;
  }

  ScenarioReport report;
  report.name = s_.name;
  report.seed = seed_;
  report.sim_time_s = sim_s;
  report.failovers_s = failovers_s_;
  // Ground truth before anything stops.
  {
    grpc::ClientContext context;
    WithDeadline(&context);
    v1::GroundTruth truth;
    if (simulator_->GetGroundTruth(&context, v1::GetGroundTruthRequest{}, &truth).ok()) {
      report.min_separation_m = truth.min_separation_m();
      for (const v1::RobotGroundTruth& robot : truth.robots()) {
        if (figures_.count(robot.robot_id())) {
          RobotFigures& f = figures_[robot.robot_id()];
          f.contacts = static_cast<int>(robot.collisions());
          absl::StatusOr<Pose2> pose = fleetnav::FromProto(robot.pose());
          if (pose.ok()) f.final_pose = *pose;
        }
        report.contacts += static_cast<int>(robot.collisions());
      }
      for (const v1::Contact& contact : truth.contacts()) {  // oldest first
        auto it = figures_.find(contact.robot_id());
        if (it == figures_.end() || it->second.first_contact_s) continue;
        it->second.first_contact_s = static_cast<double>(contact.sim_time_ns()) * 1e-9;
        it->second.first_contact_with = contact.other();
      }
    } else {
      report.failures.push_back("the simulator's ground truth could not be read at the end");
    }
  }
  for (auto& [id, agent] : agents_) {
    agent->Stop(SIGTERM, 10.0);
    agents_cpu_s_ += agent->cpu_s().value_or(0.0);
  }
  sim_->Stop(SIGTERM, 10.0);
  report.server_cpu_s = server_cpu_s_;
  for (ServerProcess& server : servers_) {
    server.process->Stop(SIGTERM, 10.0);
    report.server_cpu_s += server.process->cpu_s().value_or(0.0);
  }
  report.sim_cpu_s = sim_->cpu_s().value_or(0.0);
  report.agents_cpu_s = agents_cpu_s_;
  // A single fleetnavd logs its dispatcher's figures at exit (replicas do not).
  ReadAssigningPasses(ReadWholeFile(ServerLog(0, servers_[0].starts)), &report);
  report.wall_time_s = SecondsSince(wall_start);
  report.real_time_factor = report.wall_time_s > 0 ? report.sim_time_s / report.wall_time_s : 0;
  Finish(&report);
  return report;
}

void Run::Finish(ScenarioReport* report) {
  // Figures from the recordings: the truth at 10 Hz of sim time, each agent's estimates.
  const auto truth = ReadTrajectories(Path("truth.csv"));
  for (auto& [id, f] : figures_) {
    const auto t = truth.find(id);
    if (t == truth.end()) continue;
    for (size_t i = 1; i < t->second.size(); ++i) {
      f.distance_m +=
          std::hypot(t->second[i].x - t->second[i - 1].x, t->second[i].y - t->second[i - 1].y);
    }
    const auto estimates = ReadTrajectories(Path(absl::StrCat("estimate-", id, ".csv")));
    const auto e = estimates.find(id);
    if (e == estimates.end()) continue;
    for (const Sample& est : e->second) {
      const auto near =
          std::lower_bound(t->second.begin(), t->second.end(), est.t_s,
                           [](const Sample& a, double time_s) { return a.t_s < time_s; });
      if (near == t->second.end() || std::abs(near->t_s - est.t_s) > 0.1) continue;
      f.max_loc_error_m = std::max(f.max_loc_error_m, std::hypot(near->x - est.x, near->y - est.y));
    }
  }
  for (const JobOutcome& job : jobs_) {
    if (IsEnd(job.state) && figures_.count(job.robot_id)) ++figures_[job.robot_id].jobs;
  }
  double waited_s = 0.0;
  for (auto& [id, f] : figures_) {
    report->robots.push_back(f);
    waited_s += f.waiting_s;
  }
  if (!figures_.empty() && report->sim_time_s > 0.0) {
    report->waiting_share = waited_s / (static_cast<double>(figures_.size()) * report->sim_time_s);
  }
  for (const RobotFigures& f : report->robots) {
    double last_end_s = -1.0;
    for (const JobOutcome& job : jobs_) {
      if (job.robot_id == f.robot_id) last_end_s = std::max(last_end_s, job.end_sim_s);
    }
    if (last_end_s >= 0.0) {
      report->no_wait_end_s = std::max(report->no_wait_end_s, last_end_s - f.waiting_s);
    }
  }
  report->jobs = jobs_;
  // Expectations.
  for (const JobOutcome& job : jobs_) {
    if (job.state != job.expected) {
      report->failures.push_back(absl::StrCat("job ", job.name, " ended ", job.state, " (expected ",
                                              job.expected, ")",
                                              job.reason.empty() ? "" : ": " + job.reason));
    }
  }
  if (report->contacts > s_.expect.max_contacts) {
    // The earliest contact, to find it in the replay.
    const RobotFigures* earliest = nullptr;
    for (const RobotFigures& robot : report->robots) {
      if (robot.first_contact_s &&
          (earliest == nullptr || *robot.first_contact_s < *earliest->first_contact_s)) {
        earliest = &robot;
      }
    }
    const std::string first =
        earliest == nullptr
            ? ""
            : absl::StrFormat(": %s first touched %s at %.2f s of sim time", earliest->robot_id,
                              earliest->first_contact_with, *earliest->first_contact_s);
    report->failures.push_back(absl::StrCat(report->contacts, " contact episode(s) (at most ",
                                            s_.expect.max_contacts, " expected)", first));
  }
  if (s_.expect.min_separation_m && report->min_separation_m < *s_.expect.min_separation_m) {
    report->failures.push_back(absl::StrFormat("min separation %.3f m (at least %.3f m expected)",
                                               report->min_separation_m,
                                               *s_.expect.min_separation_m));
  }
  for (const auto& [robot_id, most_s] : s_.expect.max_waiting_s) {
    const double waited_s = figures_[robot_id].waiting_s;
    if (waited_s > most_s) {
      report->failures.push_back(absl::StrFormat(
          "%s was held by traffic coordination for %.1f s (at most %.1f s expected)", robot_id,
          waited_s, most_s));
    }
  }
  if (report->sim_time_s >= s_.expect.deadline_s) {
    report->failures.push_back(
        absl::StrFormat("deadline of %.0f s of sim time reached", s_.expect.deadline_s));
  }
  report->passed = report->failures.empty();
  // The picture: map, true and estimated paths.
  if (!opt_.picture_path.empty()) {
    // Whole lines only: a process stopped mid-write leaves a cut last line.
    auto whole_lines = [](std::string text) { return text.substr(0, text.rfind('\n') + 1); };
    std::ofstream all(Path("trajectories.csv"));
    all << whole_lines(ReadWholeFile(Path("truth.csv")));
    for (const ScenarioRobot& robot : s_.robots) {
      all << whole_lines(ReadWholeFile(Path(absl::StrCat("estimate-", robot.robot_id, ".csv"))));
    }
    all.close();
    ChildProcess render({bin_.sim, "--world", s_.world_path, "--render", opt_.picture_path,
                         "--trajectories", Path("trajectories.csv")},
                        Path("render.out"), Path("render.log"));
    if (render.Wait(120.0) != 0) {
      report->failures.push_back(absl::StrCat("the picture was not drawn: ", render.Stderr()));
      report->passed = false;
    }
  }
  if (keep_) report->work_dir = work_;
}

}  // namespace

absl::StatusOr<Binaries> Binaries::Find(const std::string& self) {
  const fs::path dir = fs::absolute(fs::path(self)).parent_path();
  Binaries b;
  const std::pair<std::string*, std::pair<const char*, const char*>> wanted[] = {
      {&b.server, {"fleetnavd", "server"}},
      {&b.sim, {"fleetnav-sim", "sim"}},
      {&b.agent, {"fleetnav-agent", "robot_agent"}},
      {&b.ctl, {"fleetnavctl", "tools"}}};
  for (const auto& [slot, names] : wanted) {
    for (const fs::path& candidate :
         {dir / names.first, dir.parent_path() / names.second / names.first}) {
      if (fs::exists(candidate)) {
        *slot = candidate.string();
        break;
      }
    }
    if (slot->empty()) {
      return absl::NotFoundError(absl::StrCat(names.first, " was not found next to ", self,
                                              " nor in the build tree beside it"));
    }
  }
  return b;
}

absl::StatusOr<ScenarioReport> RunScenario(const Scenario& scenario, const Binaries& binaries,
                                           const RunOptions& options) {
  Run run(scenario, binaries, options);
  return run.Execute();
}

}  // namespace fleetnav::scenario
