#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_state.hpp"

namespace fleetnav {

/// A job's life: queued → assigned → running → succeeded | failed | cancelled. A running job
/// whose robot drops is paused until the robot returns or the server's lost-robot timeout acts.
enum class JobState { kQueued, kAssigned, kRunning, kPaused, kSucceeded, kFailed, kCancelled };

/// What happens to a paused job whose robot stays away past the timeout.
enum class RequeuePolicy { kFail, kRequeue };

enum class JobEventType {
  kQueued,
  kAssigned,
  kStarted,
  kActionStarted,
  kActionFinished,
  kProgress,
  kWaitingForTraffic,
  kModeSwitch,
  kPaused,
  kResumed,
  kSucceeded,
  kFailed,
  kCancelled,
  kBumper,            ///< the bumper closed: the robot stopped (the job then fails)
  kLocalizationLost,  ///< the estimate diverged: the robot stopped (the job then fails)
};

/// A job: run a route (by name, pinned to a version when accepted) or go to a goal, with any
/// capable robot or a named one. Times are Unix milliseconds. Value type.
struct Job {
  std::string job_id;
  JobState state = JobState::kQueued;
  std::string route_name;
  uint32_t route_version = 0;
  std::string map_id;  ///< the map the job runs on (the route's map, or the goal's)
  std::optional<Pose2> goal;
  std::string requested_robot_id;
  std::string assigned_robot_id;
  int priority = 0;
  std::string idempotency_key;
  RequeuePolicy on_robot_lost = RequeuePolicy::kFail;
  int64_t created_unix_ms = 0;
  int64_t updated_unix_ms = 0;
  double progress_fraction = 0.0;
  std::string reason;
};

/// One transition or report in a job's life, kept in order.
struct JobEvent {
  std::string job_id;
  int64_t sequence = 0;  ///< 1, 2, … per job
  JobEventType type = JobEventType::kQueued;
  int64_t unix_ms = 0;
  std::string robot_id;
  int action_index = -1;
  double progress_fraction = 0.0;
  NavigationMode mode = NavigationMode::kIdle;
  std::string reason;
  JobState state = JobState::kQueued;  ///< the job's state after this event
};

inline bool IsTerminal(JobState state) {
  return state == JobState::kSucceeded || state == JobState::kFailed ||
         state == JobState::kCancelled;
}

inline std::string_view JobStateName(JobState state) {
  switch (state) {
    case JobState::kQueued:
      return "queued";
    case JobState::kAssigned:
      return "assigned";
    case JobState::kRunning:
      return "running";
    case JobState::kPaused:
      return "paused";
    case JobState::kSucceeded:
      return "succeeded";
    case JobState::kFailed:
      return "failed";
    case JobState::kCancelled:
      return "cancelled";
  }
  return "unknown";
}

/// What an operator asks for when submitting a job (SubmitJob), before it is checked.
struct SubmitJobRequest {
  std::string route_name;   ///< either a route …
  std::string goal_map_id;  ///< … or a goal on a map
  std::optional<Pose2> goal;
  std::string robot_id;  ///< empty: any capable robot
  int priority = 0;
  std::string idempotency_key;
  RequeuePolicy on_robot_lost = RequeuePolicy::kFail;
};

/// Which jobs a listing asks for (ListJobs), one page at a time.
struct JobFilter {
  std::vector<JobState> states;  ///< empty: every state
  std::string robot_id;          ///< empty: any robot (matches requested or assigned)
  std::string map_id;            ///< empty: any map
  int page_size = 100;
  std::string page_token;  ///< from the previous page; empty: the first page
};

}  // namespace fleetnav
