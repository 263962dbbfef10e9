#include "fleetnav/proto/assignment_convert.hpp"

#include <algorithm>
#include <memory>
#include <string>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/proto/geometry_convert.hpp"
#include "fleetnav/proto/job_convert.hpp"
#include "fleetnav/proto/route_convert.hpp"

namespace fleetnav {

v1::Assignment ToProto(const JobAssignment& assignment) {
  v1::Assignment wire;
  *wire.mutable_job() = ToProto(assignment.job);
  *wire.mutable_route() = ToProto(*assignment.route);
  wire.set_route_version(assignment.route_version);
  wire.set_map_id(assignment.job.map_id);
  wire.set_map_version(assignment.map_version);
  wire.set_marker_set_version(assignment.marker_set_version);
  wire.set_zone_set_version(assignment.zone_set_version);
  wire.set_resume_action_index(assignment.resume.action_index);
  wire.set_resume_action_fraction(assignment.resume.action_fraction);
  return wire;
}

absl::StatusOr<JobAssignment> FromProto(const v1::Assignment& wire) {
  JobAssignment assignment;
  ASSIGN_OR_RETURN(assignment.job, FromProto(wire.job()));
  ASSIGN_OR_RETURN(Route route, FromProto(wire.route()));
  assignment.route = std::make_shared<const Route>(std::move(route));
  // The assignment's map is the job's; an older server sent it only here.
  if (assignment.job.map_id.empty()) assignment.job.map_id = wire.map_id();
  assignment.route_version = wire.route_version();
  assignment.map_version = wire.map_version();
  assignment.marker_set_version = wire.marker_set_version();
  assignment.zone_set_version = wire.zone_set_version();
  assignment.resume = RoutePosition{wire.resume_action_index(), wire.resume_action_fraction()};
  return assignment;
}

v1::Command ToProto(const JobCommand& command) {
  v1::Command wire;
  wire.set_type(command.type == JobCommandType::kPause    ? v1::Command::TYPE_PAUSE
                : command.type == JobCommandType::kResume ? v1::Command::TYPE_RESUME
                                                          : v1::Command::TYPE_CANCEL);
  wire.set_job_id(command.job_id);
  wire.set_reason(command.reason);
  return wire;
}

absl::StatusOr<JobCommand> FromProto(const v1::Command& wire) {
  JobCommand command;
  switch (wire.type()) {
    case v1::Command::TYPE_PAUSE:
      command.type = JobCommandType::kPause;
      break;
    case v1::Command::TYPE_RESUME:
      command.type = JobCommandType::kResume;
      break;
    case v1::Command::TYPE_CANCEL:
      command.type = JobCommandType::kCancel;
      break;
    default:
      return absl::InvalidArgumentError(absl::StrCat("command.type: unspecified or unknown value ",
                                                     static_cast<int>(wire.type())));
  }
  command.job_id = wire.job_id();
  command.reason = wire.reason();
  return command;
}

v1::TrafficClearance ToProto(const ClearanceNotice& clearance) {
  v1::TrafficClearance wire;
  wire.set_job_id(clearance.job_id);
  wire.set_cleared_up_to_action(clearance.cleared_up_to_action);
  for (const TrafficDependency& wait : clearance.waits) {
    v1::DependencyEdge* edge = wire.add_waits_for();
    edge->set_from_robot_id(wait.from_robot_id);
    edge->set_from_action(static_cast<uint32_t>(std::max(wait.from_action, 0)));
    edge->set_to_robot_id(wait.to_robot_id);
    edge->set_to_action(static_cast<uint32_t>(std::max(wait.to_action, 0)));
  }
  wire.set_wait_reason(clearance.wait_reason);
  if (clearance.hold) {
    wire.mutable_hold()->set_segment(clearance.hold->segment);
    *wire.mutable_hold()->mutable_gate() = ToProto(clearance.hold->gate);
  }
  for (const ActionPath& path : clearance.paths) {
    v1::ActionPath* planned = wire.add_paths();
    planned->set_action(path.action_index);
    planned->set_id(path.id);
    for (const Eigen::Vector2d& waypoint : path.waypoints_m) {
      *planned->add_waypoints() = ToProto(waypoint);
    }
  }
  return wire;
}

absl::StatusOr<JobCommand> FromProto(const v1::TrafficClearance& clearance) {
  JobCommand command{JobCommandType::kClearance, clearance.job_id(), clearance.wait_reason(),
                     clearance.cleared_up_to_action(), std::nullopt};
  if (clearance.has_hold()) {
    ASSIGN_OR_RETURN(const Pose2 gate, FromProto(clearance.hold().gate(), "clearance.hold.gate"));
    command.hold = SegmentHold{clearance.cleared_up_to_action(), clearance.hold().segment(), gate};
  }
  for (int i = 0; i < clearance.paths_size(); ++i) {
    const v1::ActionPath& wire = clearance.paths(i);
    const std::string field = absl::StrCat("clearance.paths[", i, "]");
    if (wire.action() < 0 || wire.action() > clearance.cleared_up_to_action()) {
      return absl::InvalidArgumentError(absl::StrCat(field, ".action: ", wire.action(),
                                                     " is not a cleared action (0..",
                                                     clearance.cleared_up_to_action(), ")"));
    }
    ActionPath path{wire.action(), wire.id(), {}};
    for (int k = 0; k < wire.waypoints_size(); ++k) {
      ASSIGN_OR_RETURN(Eigen::Vector2d waypoint,
                       FromProto(wire.waypoints(k), absl::StrCat(field, ".waypoints[", k, "]")));
      path.waypoints_m.push_back(waypoint);
    }
    command.paths.push_back(std::move(path));
  }
  return command;
}

}  // namespace fleetnav
