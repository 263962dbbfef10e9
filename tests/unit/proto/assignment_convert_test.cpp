#include "fleetnav/proto/assignment_convert.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "fleetnav/proto/telemetry_convert.hpp"

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

JobAssignment Feeding() {
  JobAssignment a;
  a.job.job_id = "job-7";
  a.job.route_name = "feed";
  a.job.map_id = "barn";
  a.job.assigned_robot_id = "lely1";
  Route route;
  route.name = "feed";
  route.map_id = "barn";
  route.actions = {RouteAction{StraightAction{5.0, 0.25}, {}},
                   RouteAction{TurnAction{1.5, 0.3}, {}}};
  a.route = std::make_shared<const Route>(route);
  a.route_version = 4;
  a.map_version = 3;
  a.marker_set_version = 2;
  a.resume = RoutePosition{1, 0.25};
  return a;
}

TEST(AssignmentConvertTest, AnAssignmentCrossesTheWireUnchanged) {
  const JobAssignment sent = Feeding();
  const v1::Assignment wire = ToProto(sent);
  EXPECT_EQ(wire.map_id(), "barn");
  absl::StatusOr<JobAssignment> got = FromProto(wire);
  ASSERT_TRUE(got.ok()) << got.status();
  EXPECT_EQ(got->job.job_id, "job-7");
  EXPECT_EQ(got->job.map_id, "barn");
  EXPECT_EQ(got->job.assigned_robot_id, "lely1");
  ASSERT_EQ(got->route->actions.size(), 2u);
  EXPECT_EQ(got->route->name, "feed");
  EXPECT_EQ(got->route_version, 4u);
  EXPECT_EQ(got->map_version, 3u);
  EXPECT_EQ(got->marker_set_version, 2u);
  EXPECT_EQ(got->resume.action_index, 1);
  EXPECT_DOUBLE_EQ(got->resume.action_fraction, 0.25);
}

TEST(AssignmentConvertTest, ABadRouteIsRefusedNamingIt) {
  v1::Assignment wire = ToProto(Feeding());
  wire.mutable_route()->mutable_actions(0)->mutable_straight()->set_speed_mps(-1.0);
  absl::StatusOr<JobAssignment> got = FromProto(wire);
  ASSERT_FALSE(got.ok());
  EXPECT_EQ(got.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(got.status().message()), HasSubstr("speed"));
}

TEST(AssignmentConvertTest, CommandsAndClearancesBecomeJobCommands) {
  for (JobCommandType type :
       {JobCommandType::kPause, JobCommandType::kResume, JobCommandType::kCancel}) {
    absl::StatusOr<JobCommand> got = FromProto(ToProto(JobCommand{type, "job-7", "why"}));
    ASSERT_TRUE(got.ok()) << got.status();
    EXPECT_EQ(got->type, type);
    EXPECT_EQ(got->job_id, "job-7");
    EXPECT_EQ(got->reason, "why");
  }
  v1::Command unknown;
  unknown.set_job_id("job-7");
  EXPECT_EQ(FromProto(unknown).status().code(), absl::StatusCode::kInvalidArgument);

  ClearanceNotice notice{"job-7",
                         3,
                         {{"lely2", 1, "lely1", 4}, {"omni1", -1, "lely1", 4}},
                         "waits for lely2",
                         std::nullopt};
  v1::TrafficClearance clearance = ToProto(notice);
  ASSERT_EQ(clearance.waits_for_size(), 2);
  EXPECT_EQ(clearance.waits_for(0).from_robot_id(), "lely2");
  EXPECT_EQ(clearance.waits_for(0).from_action(), 1u);
  EXPECT_EQ(clearance.waits_for(0).to_robot_id(), "lely1");
  EXPECT_EQ(clearance.waits_for(0).to_action(), 4u);
  EXPECT_EQ(clearance.waits_for(1).from_action(), 0u);  // before omni1's first action
  EXPECT_FALSE(clearance.has_hold());
  absl::StatusOr<JobCommand> cleared = FromProto(clearance);
  ASSERT_TRUE(cleared.ok());
  EXPECT_EQ(cleared->type, JobCommandType::kClearance);
  EXPECT_EQ(cleared->cleared_up_to_action, 3);
  EXPECT_EQ(cleared->reason, "waits for lely2");
  EXPECT_FALSE(cleared->hold.has_value());  // the whole of action 3

  // Within action 3 only up to a gate.
  clearance.mutable_hold()->set_segment(2);
  clearance.mutable_hold()->mutable_gate()->set_x_m(4.5);
  clearance.mutable_hold()->mutable_gate()->set_yaw_rad(1.0);
  cleared = FromProto(clearance);
  ASSERT_TRUE(cleared.ok());
  ASSERT_TRUE(cleared->hold.has_value());
  EXPECT_EQ(cleared->hold->action_index, 3);
  EXPECT_EQ(cleared->hold->segment, 2);
  EXPECT_DOUBLE_EQ(cleared->hold->gate.x_m(), 4.5);
  EXPECT_DOUBLE_EQ(cleared->hold->gate.yaw_rad(), 1.0);
  // A hold sent by the server arrives as it was sent.
  notice.hold = SegmentHold{3, 2, Pose2(4.5, -1.0, 1.0)};
  const absl::StatusOr<JobCommand> round = FromProto(ToProto(notice));
  ASSERT_TRUE(round.ok());
  ASSERT_TRUE(round->hold.has_value());
  EXPECT_EQ(round->hold->segment, 2);
  EXPECT_DOUBLE_EQ(round->hold->gate.y_m(), -1.0);
  EXPECT_DOUBLE_EQ(round->hold->gate.yaw_rad(), 1.0);
  // A gate that is not finite is refused, naming the field.
  clearance.mutable_hold()->mutable_gate()->set_y_m(std::nan(""));
  cleared = FromProto(clearance);
  EXPECT_EQ(cleared.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(cleared.status().message()), ::testing::HasSubstr("clearance.hold.gate"));
}

TEST(AssignmentConvertTest, PlannedPathsCrossTheWireWithTheirClearance) {
  ClearanceNotice notice{"job-7", 2, {}, "", std::nullopt};
  notice.paths.push_back(ActionPath{1, 41, {{1.0, 2.0}, {3.5, -1.25}}});
  notice.paths.push_back(ActionPath{2, 42, {}});
  absl::StatusOr<JobCommand> got = FromProto(ToProto(notice));
  ASSERT_TRUE(got.ok()) << got.status();
  ASSERT_EQ(got->paths.size(), 2u);
  EXPECT_EQ(got->paths[0], notice.paths[0]);
  EXPECT_EQ(got->paths[1], notice.paths[1]);
  // A path for an action not cleared, or a waypoint that is not finite, is refused naming it.
  notice.paths[1].action_index = 3;
  got = FromProto(ToProto(notice));
  EXPECT_EQ(got.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(got.status().message()),
              ::testing::HasSubstr("clearance.paths[1].action"));
  notice.paths[1].action_index = 2;
  notice.paths[0].waypoints_m[1].x() = std::nan("");
  got = FromProto(ToProto(notice));
  EXPECT_EQ(got.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(got.status().message()),
              ::testing::HasSubstr("clearance.paths[0].waypoints[1]"));
  // An agent's hello says whether it drives planned paths.
  RobotIdentity identity;
  identity.robot_id = "omni1";
  identity.model = MecanumPlatformModel();
  identity.planned_paths = true;
  absl::StatusOr<RobotIdentity> back = FromProto(ToProto(identity));
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_TRUE(back->planned_paths);
}

}  // namespace
}  // namespace fleetnav
