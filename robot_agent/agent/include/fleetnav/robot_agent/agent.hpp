#pragma once

#include <optional>
#include <string>

#include "absl/status/statusor.h"
#include "fleetnav/core/robot_state.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/robot_agent/hal.hpp"
#include "fleetnav/robot_agent/job_channel.hpp"
#include "fleetnav/robot_agent/route_executor.hpp"
#include "fleetnav/robot_agent/telemetry_sink.hpp"
#include "fleetnav/robot_agent/wheel_odometry.hpp"

namespace fleetnav::agent {

struct AgentParams {
  /// Telemetry period in robot (sim) time; 0.05 s = 20 Hz, above the 10 Hz the server needs.
  double telemetry_period_s = 0.05;
  /// The robot's pose in the map when odometry starts (map → odom is this pose).
  Pose2 initial_pose_in_map;
  /// Return from Run() once the route has ended (after the robot has stopped).
  bool exit_when_done = true;
  /// Ticks of standstill commanded after the route ends, so the robot settles.
  int settle_ticks = 25;
  /// In job mode, return after this many jobs have ended (0: run until the HAL ends).
  int max_jobs = 0;
  absl::Status Validate() const;
};

/// How a Run() ended.
struct AgentResult {
  ExecutionState state = ExecutionState::kRunning;
  std::string failure_reason;
  int jobs_finished = 0;  ///< jobs from the server that ended (any outcome)
  Pose2 final_pose_in_map;
  uint64_t ticks = 0;
  uint64_t telemetry_sent = 0;
};

/// The agent's control loop: per tick, read a frame from the HAL, update wheel odometry, step
/// the route executor, send the command, and publish telemetry every telemetry_period_s of
/// robot time. The pose in map is initial_pose_in_map ∘ pose_in_odom until localization lands.
/// Two ways to get work: a route given at start (run once, then return), or jobs from a
/// JobChannel (the server): one job at a time, reporting action started/finished, succeeded,
/// failed or cancelled; pause holds the robot still. Runs on the caller's thread until the HAL
/// ends (or the given route is done, or max_jobs jobs have ended).
class Agent {
 public:
  Agent(const RobotModel& model, RobotHal* hal, TelemetrySink* telemetry,
        std::optional<Route> route, AgentParams params, JobChannel* jobs = nullptr);

  absl::StatusOr<AgentResult> Run();

 private:
  Telemetry MakeTelemetry(int64_t stamp_ns, const ExecutorOutput& output) const;
  /// Takes new assignments and commands, and reports the current job's events.
  void ServeJobs(const ExecutorOutput& output, int64_t stamp_ns, AgentResult* result);
  void ReportJobEvent(JobEventType type, int action_index, const std::string& reason);

  RobotModel model_;
  RobotHal* hal_;
  TelemetrySink* telemetry_;
  std::optional<RouteExecutor> executor_;
  AgentParams params_;
  WheelOdometry odometry_;
  uint64_t sequence_ = 0;
  JobChannel* jobs_;
  std::string current_job_id_;
  int reported_action_ = -1;
  bool paused_ = false;
};

}  // namespace fleetnav::agent
