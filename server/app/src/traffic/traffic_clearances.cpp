// TrafficCoordinator, part three: decisions told to robots: the steps (actions and their
// segments) converted to actions, the reasons in words, and the gates robots have passed.
#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/segment_gate.hpp"
#include "fleetnav/planner/coordination/make_way.hpp"
#include "fleetnav/planner/coordination/route_segments.hpp"
#include "fleetnav/planner/single_robot/planner_factory.hpp"
#include "fleetnav/server/traffic/traffic_coordinator.hpp"

namespace fleetnav::server {
namespace {

/// "action 3 (free_navigation)", or "segment 2 of 5 of action 3 (free_navigation)" when the
/// segment is not the action's last.
std::string StepName(int action, int segment, int segments, const Route& route) {
  std::string name = absl::StrCat("action ", action);
  if (action < static_cast<int>(route.actions.size())) {
    absl::StrAppend(&name, " (", std::string(ActionTypeName(route.actions[action].params)), ")");
  }
  if (segment + 1 < segments) {
    name = absl::StrCat("segment ", segment + 1, " of ", segments, " of ", name);
  }
  return name;
}

}  // namespace

int TrafficCoordinator::FirstStepOf(const Tracked& tracked, int action) {
  return FirstStepOf(tracked.steps, action);
}

int TrafficCoordinator::FirstStepOf(const std::vector<Step>& steps, int action) {
  const auto it = std::lower_bound(steps.begin(), steps.end(), action,
                                   [](const Step& step, int a) { return step.action < a; });
  return static_cast<int>(it - steps.begin());
}

int TrafficCoordinator::ActionOfStep(const Tracked& tracked, int step) {
  return step >= 0 && step < static_cast<int>(tracked.steps.size()) ? tracked.steps[step].action
                                                                    : step;
}

std::string TrafficCoordinator::Describe(const planner::TrafficClearanceDecision& d,
                                         const std::map<std::string, const Tracked*>& jobs_on_map) {
  if (d.waits.empty()) return "";
  const planner::TrafficWait& wait = d.waits.front();
  auto waiting = jobs_on_map.find(d.robot_id);
  const int action =
      waiting != jobs_on_map.end() ? ActionOfStep(*waiting->second, wait.action) : wait.action;
  std::string blocker_step = "its last action";
  auto blocker = jobs_on_map.find(wait.blocker_robot_id);
  if (blocker != jobs_on_map.end() && wait.blocker_action >= 0 &&
      wait.blocker_action < static_cast<int>(blocker->second->steps.size())) {
    const Step& step = blocker->second->steps[wait.blocker_action];
    blocker_step =
        StepName(step.action, step.segment, step.segments, *blocker->second->assignment.route);
  }
  const std::string next = absl::StrCat("action ", action, " waits for ");
  if (d.deadlocked) {
    return absl::StrCat(next, wait.blocker_robot_id,
                        ": the routes block each other; it runs when that job ends");
  }
  if (wait.blocker_action < 0) {
    return absl::StrCat(next, wait.blocker_robot_id, ", which stands in its way");
  }
  return absl::StrCat(next, wait.blocker_robot_id, " to finish ", blocker_step);
}

ClearanceNotice TrafficCoordinator::Notice(const Tracked& tracked,
                                           const planner::TrafficClearanceDecision& d,
                                           const std::map<std::string, const Tracked*>& jobs_on_map,
                                           const std::string& reason) {
  ClearanceNotice notice{tracked.assignment.job.job_id, -1, {}, reason, std::nullopt};
  if (d.cleared_up_to >= 0 && d.cleared_up_to < static_cast<int>(tracked.steps.size())) {
    const Step& step = tracked.steps[d.cleared_up_to];
    notice.cleared_up_to_action = step.action;
    if (step.gate) notice.hold = SegmentHold{step.action, step.segment, *step.gate};
  }
  if (const std::optional<SegmentHold>& stood = tracked.hold_under_way;
      stood && d.cleared_up_to < FirstStepOf(tracked, stood->action_index)) {
    // Its way was planned again in the middle of the action: it stands where it was.
    notice.cleared_up_to_action = stood->action_index;
    notice.hold = stood;
  }
  for (const auto& [action, path] : tracked.paths) {
    if (action >= tracked.start_action && action <= notice.cleared_up_to_action) {
      notice.paths.push_back(path);
    }
  }
  for (const planner::TrafficWait& wait : d.waits) {
    int blocker_action = wait.blocker_action;
    auto blocker = jobs_on_map.find(wait.blocker_robot_id);
    if (blocker != jobs_on_map.end()) {
      blocker_action = ActionOfStep(*blocker->second, wait.blocker_action);
    }
    notice.waits.push_back(
        {wait.blocker_robot_id, blocker_action, wait.robot_id, ActionOfStep(tracked, wait.action)});
  }
  return notice;
}

void TrafficCoordinator::PassGates(Tracked& tracked, const Telemetry& telemetry) {
  if (!tracked.schedule || telemetry.job_id != tracked.assignment.job.job_id) return;
  int& first = tracked.schedule->first_unfinished;
  while (first < static_cast<int>(tracked.steps.size()) &&
         tracked.steps[first].action == telemetry.action_index && tracked.steps[first].gate &&
         ReachedGate(*tracked.steps[first].gate, telemetry.pose_in_map.translation())) {
    ++first;
  }
}

}  // namespace fleetnav::server
