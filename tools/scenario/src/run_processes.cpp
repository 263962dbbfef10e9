#include <signal.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
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
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/proto/channel_credentials.hpp"
#include "fleetnav/proto/geometry_convert.hpp"
#include "fleetnav/proto/server_target.hpp"
#include "scenario_run.hpp"

namespace fleetnav::scenario::internal {

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

absl::Status Run::PrepareWorkFolder() {
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
  return absl::OkStatus();
}

absl::Status Run::StartSimulator() {
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
  return absl::OkStatus();
}

absl::Status Run::StartServers() {
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
  return absl::OkStatus();
}

absl::Status Run::LoadSite() {
  const std::string map_yaml = Path(absl::StrCat("map/", s_.map_id, ".yaml"));
  const std::string markers_yaml = Path(absl::StrCat("map/", s_.map_id, ".markers.yaml"));
  if (absl::Status st = Ctl({"map", "import", "--id", s_.map_id, map_yaml}); !st.ok()) return st;
  if (fs::exists(markers_yaml)) {
    if (absl::Status st = Ctl({"markers", "put", markers_yaml}); !st.ok()) return st;
  }
  if (!s_.zones_path.empty()) {
    if (absl::Status st = Ctl({"zones", "put", "--map", s_.map_id, s_.zones_path}); !st.ok()) {
      return st;
    }
  }
  for (const std::string& route : s_.route_paths) {
    if (absl::Status st = Ctl({"routes", "put", route}); !st.ok()) return st;
  }
  return absl::OkStatus();
}

absl::Status Run::StartAgents() {
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
  return absl::OkStatus();
}

void Run::StopProcesses(ScenarioReport* report) {
  for (auto& [id, agent] : agents_) {
    agent->Stop(SIGTERM, 10.0);
    agents_cpu_s_ += agent->cpu_s().value_or(0.0);
  }
  sim_->Stop(SIGTERM, 10.0);
  report->server_cpu_s = server_cpu_s_;
  for (ServerProcess& server : servers_) {
    server.process->Stop(SIGTERM, 10.0);
    report->server_cpu_s += server.process->cpu_s().value_or(0.0);
  }
  report->sim_cpu_s = sim_->cpu_s().value_or(0.0);
  report->agents_cpu_s = agents_cpu_s_;
}

}  // namespace fleetnav::scenario::internal
