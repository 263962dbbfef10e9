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
#include "fleetnav/robot_agent/job_runner.hpp"
#include "fleetnav/robot_agent/perception.hpp"
#include "fleetnav/robot_agent/route_executor.hpp"
#include "fleetnav/robot_agent/safety_monitor.hpp"
#include "fleetnav/robot_agent/self_filter.hpp"
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

/// The agent's control loop (Lely thesis Fig. 6.5): per tick, read a frame from the HAL, take
/// the carried load out of it (SelfFilter), update the localizer (odometry EKF, SAMCL), build
/// the perception, let the JobRunner step the job (safety, route, events) and take the
/// server's commands, send the command and publish telemetry every telemetry_period_s of robot
/// time. Work comes as a route given at start (run once, then return) or as jobs from a
/// JobChannel, one at a time (JobRunner). Runs on the caller's thread until the HAL ends (or
/// the route is done, or max_jobs jobs have ended).
class Agent {
 public:
  Agent(RouteContext context, AgentPorts ports, std::optional<Route> route, AgentParams params);

  absl::StatusOr<AgentResult> Run();

 private:
  Telemetry MakeTelemetry(int64_t stamp_ns, const ExecutorOutput& output) const;

  AgentPorts ports_;
  AgentParams params_;
  PerceptionBuilder perception_;
  SelfFilter self_filter_;
  JobRunner runner_;
  uint64_t sequence_ = 0;
  double battery_fraction_ = 1.0;  ///< as the robot last reported it
  Twist2 last_command_;
};

}  // namespace fleetnav::agent
