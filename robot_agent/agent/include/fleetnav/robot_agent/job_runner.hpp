#pragma once

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/core/job.hpp"
#include "fleetnav/core/job_assignment.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/localization/localizer.hpp"
#include "fleetnav/robot_agent/job_channel.hpp"
#include "fleetnav/robot_agent/route_executor.hpp"
#include "fleetnav/robot_agent/safety_monitor.hpp"
#include "fleetnav/robot_agent/site_source.hpp"
#include "fleetnav/robot_agent/stop_guard.hpp"
#include "fleetnav/robot_agent/zone_speed_limit.hpp"

namespace fleetnav::agent {

/// Makes the localizer for a job's site, starting from the robot's current pose in map.
using LocalizerFactory = std::function<absl::StatusOr<std::unique_ptr<localization::Localizer>>(
    const SiteData& site, const Pose2& start_in_map)>;

/// What the job runner works with: where jobs come from (null: only the route given at start),
/// where sites come from and how a localizer is made for one, and the localizer in use until a
/// job brings its site.
struct JobRunnerPorts {
  JobChannel* jobs = nullptr;
  SiteSource* sites = nullptr;
  LocalizerFactory make_localizer;
  localization::Localizer* start_localizer = nullptr;
};

/// One job at a time, apart from the agent's tick: takes assignments and commands from the
/// JobChannel (or runs the route given at start), loads each job's site and its localizer,
/// holds pause and traffic clearances, judges safety while a route runs (bumper, stall, lost
/// localization: a safety stop aborts the route), steps the route executor and reports every
/// event (actions started and finished, mode switches, bumper, the job's end). The executor
/// alone owns the carried load and the moved loads while its route runs; the runner takes them
/// back when the route is over. The tick (Agent::Run) hands it each tick's control input and
/// sends what it answers. Not thread-safe.
class JobRunner {
 public:
  JobRunner(RouteContext context, JobRunnerPorts ports, ModeParams modes, SafetyParams safety,
            std::optional<Route> route);

  /// The job's localizer, or the start's until a job brought its site.
  localization::Localizer& localizer() {
    return job_localizer_ ? *job_localizer_ : *ports_.start_localizer;
  }
  const localization::Localizer& localizer() const {
    return job_localizer_ ? *job_localizer_ : *ports_.start_localizer;
  }
  /// This tick's step of the route (standstill without one). `estimate` and `last_command`
  /// are for the safety monitor; markers detected this tick calibrate stripe actions.
  ExecutorOutput Step(const ControlInput& input, const std::vector<int>& detected_markers,
                      const localization::LocalizerEstimate& estimate, const Twist2& last_command);
  /// After the tick's command is decided: the server's commands, the current job's end and
  /// the next assignment (job mode only).
  void Serve(const ExecutorOutput& output);

  const std::string& job_id() const { return job_id_; }
  /// What the robot carries now (the executor's while a route runs).
  std::optional<Eigen::Vector2d> carried_load_m() const {
    return executor_ ? executor_->carried_load_m() : context_.carried_load_m;
  }
  /// The lift's setpoint, kept across routes.
  bool lift_raised() const { return lift_raised_; }
  /// The route's state (kRunning without a route).
  ExecutionState state() const { return executor_ ? executor_->state() : ExecutionState::kRunning; }
  absl::Status failure() const { return executor_ ? executor_->failure() : absl::OkStatus(); }
  /// Every event of the run, in order (also those sent to the server).
  const std::vector<JobEvent>& events() const { return events_; }
  int jobs_finished() const { return jobs_finished_; }
  /// The last safety stop, if any.
  SafetyStop safety_stop() const { return safety_stop_; }

 private:
  void StartRoute(Route route, const RoutePosition& from = {});
  /// Drops the executor, taking back what its route did to the site.
  void EndRoute();
  /// The current job is over (any outcome): the channel is told, the next may come.
  void EndJob();
  void Report(JobEventType type, int action_index, NavigationMode mode, const std::string& reason);
  /// Reports action and mode events of this tick's output.
  void ReportProgress(const ExecutorOutput& output);
  void ApplyCommand(const JobCommand& command, const ExecutorOutput& output);
  /// Loads the assignment's site and localizer when it is not the one in use; the reason when
  /// the job cannot run here.
  absl::Status PrepareSite(const JobAssignment& assignment);
  /// The robot's circumscribed radius, grown to the trolley it carries.
  double FootprintRadiusM() const;
  /// How far the robot reaches for zones and stops where its estimate puts it: its footprint's
  /// radius grown by its uncertainty (GrownReachM).
  double ReachM(const localization::LocalizerEstimate& estimate) const;
  /// Takes the zones of the job's map the server told of since the job began, when they are a
  /// version it does not use: their speed limits from now on, their no-go zones occupied on the
  /// map its next actions plan on, and the no-go zones new to it kept like stopped zones
  /// (closed_zones_) while the action in hand, planned without them, runs.
  void TakeZonesTold();

  RouteContext context_;  ///< the site in use (its map with no-go zones occupied); the loads
  /// The zones of the site in use (speed limits held each tick); nullopt: none.
  std::optional<ZoneSet> zones_;
  uint32_t zone_version_ = 0;                      ///< of zones_ (0: none)
  std::shared_ptr<const OccupancyGrid> site_map_;  ///< the site's map as stored (no zones)
  /// No-go zones put while the action in hand runs, planned without them: it brakes short of
  /// them (and fleetnavd plans it a way round) until an action starts again
  /// (closed_since_start_: the executor's actions_started() when they were taken).
  std::vector<RobotStop> closed_zones_;
  int closed_since_start_ = 0;
  ZoneSpeedParams zone_speed_;
  JobRunnerPorts ports_;
  ModeParams modes_;
  SafetyMonitor safety_;
  std::optional<RouteExecutor> executor_;
  std::string job_id_;
  int reported_action_ = -1;
  int finished_action_ = -1;  ///< the last action reported finished
  JobCommand clearance_;      ///< the latest traffic clearance, of any job
  bool paused_ = false;
  /// An operator's stop applies, or the robot has not heard the server for
  /// stop_after_link_loss_s_: it stands, its job held where it is, until that ends.
  bool stopped_ = false;
  double stop_after_link_loss_s_ = 1.0;  ///< SafetyParams::stop_after_link_loss_s
  double link_lost_s_ = 0.0;             ///< robot time since the server was last heard
  std::string site_map_id_;              ///< the map of the job in hand (stops of its zones apply)
  bool end_reported_ = false;
  bool lift_raised_ = false;
  std::unique_ptr<localization::Localizer> job_localizer_;
  std::string site_key_;  ///< map id and versions of the site in use ("" : the start's)
  std::vector<JobEvent> events_;
  int jobs_finished_ = 0;
  SafetyStop safety_stop_ = SafetyStop::kNone;
};

}  // namespace fleetnav::agent
