#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/job.hpp"
#include "fleetnav/core/robot_state.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/localization/localizer.hpp"
#include "fleetnav/robot_agent/hal.hpp"
#include "fleetnav/robot_agent/job_channel.hpp"
#include "fleetnav/robot_agent/perception.hpp"
#include "fleetnav/robot_agent/route_executor.hpp"
#include "fleetnav/robot_agent/safety_monitor.hpp"
#include "fleetnav/robot_agent/site_source.hpp"
#include "fleetnav/robot_agent/telemetry_sink.hpp"

namespace fleetnav::agent {

struct AgentParams {
  /// Telemetry period in robot (sim) time; 0.05 s = 20 Hz, above the 10 Hz the server needs.
  double telemetry_period_s = 0.05;
  /// Return from Run() once the route has ended (after the robot has stopped).
  bool exit_when_done = true;
  /// Ticks of standstill commanded after the route ends, so the robot settles.
  int settle_ticks = 25;
  /// In job mode, return after this many jobs have ended (0: run until the HAL ends).
  int max_jobs = 0;
  /// Ultrasonic readings at or beyond this range are "no echo".
  double ultrasonic_range_max_m = 2.5;
  /// Laser returns within this of a carried trolley's outline are its own legs (dropped).
  double load_mask_margin_m = 0.05;
  ModeParams modes;
  SafetyParams safety;
  absl::Status Validate() const;
};

/// Makes the localizer for a job's site, starting from the robot's current pose in map.
using LocalizerFactory = std::function<absl::StatusOr<std::unique_ptr<localization::Localizer>>(
    const SiteData& site, const Pose2& start_in_map)>;

/// The agent's collaborators: the robot's hardware, its localization, where telemetry goes,
/// and (in job mode) the server's job channel and, to localize on each job's own map and
/// marker set, where sites come from and how a localizer is made for one.
struct AgentPorts {
  RobotHal* hal = nullptr;
  localization::Localizer* localizer = nullptr;  ///< until a job brings its site
  TelemetrySink* telemetry = nullptr;
  JobChannel* jobs = nullptr;  ///< null: run the given route once
  SiteSource* sites = nullptr;
  LocalizerFactory make_localizer;
};

/// How a Run() ended.
struct AgentResult {
  ExecutionState state = ExecutionState::kRunning;
  std::string failure_reason;
  int jobs_finished = 0;  ///< jobs from the server that ended (any outcome)
  Pose2 final_pose_in_map;
  uint64_t ticks = 0;
  double sim_time_s = 0.0;  ///< robot time from the first frame to the last
  uint64_t telemetry_sent = 0;
  SafetyStop safety_stop = SafetyStop::kNone;
  /// Every event of the run (also those sent to the server), in order.
  std::vector<JobEvent> events;
  /// Marker calibrations the localizer applied, in order.
  std::vector<localization::MarkerCalibration> calibrations;
};

/// The agent's control loop (Lely thesis Fig. 6.5): per tick, read a frame from the HAL,
/// update the localizer (odometry EKF, SAMCL), build the perception, let the safety monitor
/// judge (bumper, stall, lost localization: safety stop over every navigation mode), step the
/// route executor on the estimated pose, send the command, report events (action started and
/// finished, mode switches with their reason, bumper, localization lost, the end of the job)
/// and publish telemetry every telemetry_period_s of robot time. Work comes as a route given at
/// start (run once, then return) or as jobs from a JobChannel, one at a time; pause holds the
/// robot still. Runs on the caller's thread until the HAL ends (or the route is done, or
/// max_jobs jobs have ended).
class Agent {
 public:
  Agent(RouteContext context, AgentPorts ports, std::optional<Route> route, AgentParams params);

  absl::StatusOr<AgentResult> Run();

 private:
  Telemetry MakeTelemetry(int64_t stamp_ns, const ExecutorOutput& output) const;
  /// Drops the laser returns of the trolley the robot carries (its legs ride along in view).
  void MaskLoad(const Eigen::Vector2d& load_size_m, SensorFrame* frame) const;
  /// Takes new assignments and commands, and reports the current job's end.
  void ApplyCommand(const JobCommand& command, const ExecutorOutput& output, AgentResult* result);
  void ServeJobs(const ExecutorOutput& output, AgentResult* result);
  /// Reports action and mode events of this tick's output.
  void ReportProgress(const ExecutorOutput& output, AgentResult* result);
  void Report(JobEventType type, int action_index, NavigationMode mode, const std::string& reason,
              AgentResult* result);
  void StartRoute(Route route, const RoutePosition& from = {});
  /// Loads the assignment's site and localizer when it is not the one in use; the reason when
  /// the job cannot run here.
  absl::Status PrepareSite(const JobAssignment& assignment);
  localization::Localizer& localizer() {
    return job_localizer_ ? *job_localizer_ : *ports_.localizer;
  }
  const localization::Localizer& localizer() const {
    return job_localizer_ ? *job_localizer_ : *ports_.localizer;
  }

  RouteContext context_;
  AgentPorts ports_;
  std::optional<RouteExecutor> executor_;
  AgentParams params_;
  PerceptionBuilder perception_;
  SafetyMonitor safety_;
  uint64_t sequence_ = 0;
  std::string current_job_id_;
  int reported_action_ = -1;
  int finished_action_ = -1;  ///< the last action reported finished
  JobCommand clearance_;      ///< the latest traffic clearance, of any job
  bool paused_ = false;
  bool end_reported_ = false;
  double battery_fraction_ = 1.0;  ///< as the robot last reported it
  /// The lift's setpoint, kept across routes (a route may end carrying; the trolley on the lift
  /// is context_.carried_load_m, which each new route starts from).
  bool lift_raised_ = false;
  std::unique_ptr<localization::Localizer> job_localizer_;
  std::string site_key_;  ///< map id and versions of the site in use ("" : the start's)
  Twist2 last_command_;
};

}  // namespace fleetnav::agent
