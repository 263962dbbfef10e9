#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/scenario/scenario.hpp"

namespace fleetnav::scenario {

/// Where the fleetnav binaries are.
struct Binaries {
  std::string server;  ///< fleetnavd
  std::string sim;     ///< fleetnav-sim
  std::string agent;   ///< fleetnav-agent
  std::string ctl;     ///< fleetnavctl
  /// Next to `self` (an installed bin folder) or in a build tree's server/, sim/,
  /// robot_agent/ and tools/ folders beside self's folder. NotFound names the missing one.
  static absl::StatusOr<Binaries> Find(const std::string& self);
};

struct RunOptions {
  std::optional<unsigned> seed;  ///< overrides the scenario's
  std::string keep_dir;  ///< keep logs, database and recordings here ("": a temp folder, removed)
  std::string picture_path;          ///< draw the run to this .png/.svg ("": none)
  std::ostream* progress = nullptr;  ///< live progress (bars on a terminal, lines otherwise)
  bool progress_is_terminal = false;
  double wall_timeout_s = 3600.0;
  /// Niceness of the agent processes (0-19; 0 leaves them as the runner). On a site each agent
  /// runs on its robot's own computer; here they share the machine with the server and the
  /// simulator, and a lower priority keeps 50 of them from delaying the server's work (they
  /// still get every idle cycle).
  int agent_niceness = 19;
  /// Niceness of the simulator (0-19), which stands for the world, not for a program of the
  /// product.
  int sim_niceness = 5;
  /// fleetnavd's database: "" a fresh SQLite file in the run's folder, or a postgresql:// URI
  /// of an empty database (needed for `replicas` above 1).
  std::string db;
};

struct JobOutcome {
  std::string name;
  std::string job_id;
  std::string robot_id;
  std::string state;     ///< queued … succeeded / failed / cancelled
  std::string expected;  ///< the end state it had to reach
  std::string reason;
  double end_sim_s = -1.0;
};

struct RobotFigures {
  std::string robot_id;
  int jobs = 0;                  ///< jobs it ran to an end
  double distance_m = 0.0;       ///< true path length
  double waiting_s = 0.0;        ///< sim time held by traffic coordination
  double max_loc_error_m = 0.0;  ///< truth vs the agent's estimate, at equal sim times
  int contacts = 0;              ///< contact episodes (world and robots)
  /// The first contact: when (sim s) and with what ("static", a robot's or a trolley's id).
  std::optional<double> first_contact_s;
  std::string first_contact_with;
  Pose2 final_pose;                ///< the true pose at the end
  std::vector<std::string> waits;  ///< each distinct reason traffic coordination held it
};

/// The outcome of one run: figures, and each expectation that failed.
struct ScenarioReport {
  std::string name;
  unsigned seed = 0;
  bool passed = false;
  std::vector<std::string> failures;
  std::vector<JobOutcome> jobs;
  std::vector<RobotFigures> robots;
  int contacts = 0;
  double min_separation_m = 0.0;  ///< between footprints; large with one robot
  double sim_time_s = 0.0;
  double wall_time_s = 0.0;
  double real_time_factor = 0.0;
  /// Share of the robots' sim time spent held by traffic coordination (all robots together).
  double waiting_share = 0.0;
  /// The no-coordination lower bound of the run's end: the latest, over the robots, of the
  /// robot's last job end minus the time it was held — when the work would have ended had
  /// traffic coordination never held anyone (0 when no job ended).
  double no_wait_end_s = 0.0;
  /// The longest stretch of sim time in which no robot moved (5 cm, in ground truth) while a
  /// submitted job had not ended (LongestStandstillS): a gridlock lasts to the run's end.
  double longest_standstill_s = 0.0;
  /// With zones (ZoneTruth, from the truth recording): no-go entries of true footprints, the
  /// first of them in words, and the highest true speed in each zone robots drove in.
  int no_go_entries = 0;
  std::string first_no_go_entry;
  std::map<std::string, double> max_speed_in_zone_mps;
  /// With one-at-a-time zones (ZoneTruth): the most robots in each at once, and the entries
  /// into one that was full (the first in words).
  std::map<std::string, int> max_robots_in_zone;
  int over_capacity_entries = 0;
  std::string first_over_capacity;
  /// With stops (StopTruth): how far a stopped robot moved at most, which and when, and
  /// entries into stopped zones.
  int stops_made = 0;
  double max_motion_while_stopped_m = 0.0;
  std::string worst_motion_while_stopped;
  int stopped_zone_entries = 0;
  /// CPU time (user + system) of fleetnavd, the simulator and all agents over the run (every
  /// start of each counted), the machine's cost of the run.
  double server_cpu_s = 0.0;
  double sim_cpu_s = 0.0;
  double agents_cpu_s = 0.0;
  /// fleetnavd's dispatcher passes that assigned jobs (replanning traffic with the new job),
  /// wall-clock milliseconds, as its last start logged them at exit (0 when it did not).
  int64_t assigning_passes = 0;
  double assigning_pass_ms_p50 = 0.0;
  double assigning_pass_ms_p99 = 0.0;
  double assigning_pass_ms_max = 0.0;
  /// Of those, the passes that assigned exactly one job: the replanning latency when a job is
  /// added (its route predicted, every robot's clearances decided again).
  int64_t one_job_passes = 0;
  double one_job_pass_ms_p50 = 0.0;
  double one_job_pass_ms_p99 = 0.0;
  double one_job_pass_ms_max = 0.0;
  /// The same passes in fleetnavd's dispatcher-thread CPU time.
  double one_job_pass_cpu_ms_p50 = 0.0;
  double one_job_pass_cpu_ms_p99 = 0.0;
  double one_job_pass_cpu_ms_max = 0.0;
  /// Traffic coordination's searches (route predictions, ways round robots that stand), in the
  /// CPU time of fleetnavd's search thread, off the dispatcher's.
  int64_t traffic_searches = 0;
  double traffic_search_cpu_ms_p50 = 0.0;
  double traffic_search_cpu_ms_p99 = 0.0;
  double traffic_search_cpu_ms_max = 0.0;
  /// With replicas: wall seconds from each kill_leader to the line of the replica that took
  /// the site over ("leading at epoch N": jobs recovered, dispatching).
  std::vector<double> failovers_s;
  std::string work_dir;  ///< kept only with RunOptions::keep_dir
};

/// Runs a scenario with the real binaries as processes (docs/scenarios.md): fleetnavd on a
/// fresh database, fleetnav-sim with the world (lockstep with every agent), one fleetnav-agent
/// per robot in job mode; uploads the world's map and markers and the routes with fleetnavctl;
/// submits the jobs and injects the faults at their sim times; ends when every job has ended or
/// at the deadline; judges by the simulator's ground truth. Errors are for the run itself (a
/// program that does not start); expectations that fail are in the report.
absl::StatusOr<ScenarioReport> RunScenario(const Scenario& scenario, const Binaries& binaries,
                                           const RunOptions& options);

/// The report as a table for people, and as one JSON object.
void PrintReport(const ScenarioReport& report, std::ostream& out);
std::string ReportJson(const ScenarioReport& report);

}  // namespace fleetnav::scenario
