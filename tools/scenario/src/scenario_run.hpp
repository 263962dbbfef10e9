#pragma once

// The scenario runner's one run (RunScenario), split by concern over run_*.cpp: processes
// (run_processes.cpp), faults (run_faults.cpp), pacing and polling (run_pacing.cpp) and the
// report (run_report.cpp). Private to tools/scenario.

#include <grpcpp/grpcpp.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/scenario/child_process.hpp"
#include "fleetnav/scenario/link_proxy.hpp"
#include "fleetnav/scenario/scenario_runner.hpp"
#include "fleetnav/scenario/zone_truth.hpp"
#include "fleetnav/v1/fleet_service.grpc.pb.h"
#include "fleetnav/v1/sim_service.grpc.pb.h"

namespace fleetnav::scenario::internal {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// Parses fleetnavd's exit line of dispatcher figures into `report` (run_report.cpp).
void ReadAssigningPasses(const std::string& log, ScenarioReport* report);
double SecondsSince(Clock::time_point start);
/// "queued", "running", … from the wire's job state.
std::string StateName(v1::JobState state);
bool IsEnd(const std::string& state);
void WithDeadline(grpc::ClientContext* context, double seconds = 2.0);
/// `command` run at `niceness` (0: as it is).
std::vector<std::string> Niced(int niceness, const std::vector<std::string>& command);

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
  // The run's phases, in order (Execute).
  /// The work folder: a kept one emptied of an earlier run's files, or a fresh temporary one.
  absl::Status PrepareWorkFolder();
  /// Every job and robot of the scenario as not yet seen.
  void StartOutcomes();
  /// Exports the world's map and markers, then starts fleetnav-sim held at tick 0.
  absl::Status StartSimulator();
  /// The development PKI with TLS, then fleetnavd (or each replica), until each answers.
  absl::Status StartServers();
  /// Imports the map, the marker set and the routes through fleetnavctl, as an operator would.
  absl::Status LoadSite();
  /// The link proxies cut_link faults need, then every agent, until all are connected.
  absl::Status StartAgents();
  /// Holds the simulation at each event and once a sim second until every job ended, the
  /// deadline passed or the wall time ran out; returns the sim time reached.
  absl::StatusOr<double> Drive(Clock::time_point wall_start);
  /// Contacts, the min separation and each robot's final pose from the simulator's ground
  /// truth (a failure when it cannot be read).
  void ReadGroundTruth(ScenarioReport* report);
  /// Stops the agents, the simulator and fleetnavd, adding up their CPU time.
  void StopProcesses(ScenarioReport* report);

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
  /// Operators' stops made (stop_zone, stop_all faults): when, of what, and when they end.
  std::vector<StopWindow> stop_windows_;
  struct StopEnd {
    double sim_s;
    std::string zone;  ///< "" for the whole fleet
  };
  std::vector<StopEnd> stop_ends_;
  std::vector<std::string> stop_failures_;  ///< stops, resumes or zone puts that failed
  /// Zone versions put during the run (put_zones faults), from when.
  std::vector<TimedZoneSet> zones_put_;
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

}  // namespace fleetnav::scenario::internal
