#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "fleetnav/proto/job_convert.hpp"

namespace fleetnav {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

TEST(JobRequestConvertTest, ASubmitAsksForARouteOrAGoal) {
  v1::SubmitJobRequest route;
  route.set_route_name("feed-round");
  route.set_robot_id("lely1");
  route.set_priority(3);
  route.set_idempotency_key("k-1");
  route.set_on_robot_lost(v1::REQUEUE_POLICY_REQUEUE);
  const absl::StatusOr<SubmitJobRequest> by_route = FromProto(route);
  ASSERT_TRUE(by_route.ok()) << by_route.status();
  EXPECT_EQ(by_route->route_name, "feed-round");
  EXPECT_FALSE(by_route->goal.has_value());
  EXPECT_EQ(by_route->robot_id, "lely1");
  EXPECT_EQ(by_route->priority, 3);
  EXPECT_EQ(by_route->idempotency_key, "k-1");
  EXPECT_EQ(by_route->on_robot_lost, RequeuePolicy::kRequeue);

  v1::SubmitJobRequest goal;
  goal.mutable_goal()->set_map_id("store");
  goal.mutable_goal()->mutable_goal()->set_x_m(4.0);
  goal.mutable_goal()->mutable_goal()->set_yaw_rad(1.5);
  const absl::StatusOr<SubmitJobRequest> by_goal = FromProto(goal);
  ASSERT_TRUE(by_goal.ok()) << by_goal.status();
  EXPECT_EQ(by_goal->goal_map_id, "store");
  ASSERT_TRUE(by_goal->goal.has_value());
  EXPECT_DOUBLE_EQ(by_goal->goal->x_m(), 4.0);
  EXPECT_TRUE(by_goal->route_name.empty());
}

TEST(JobRequestConvertTest, BadSubmitsAreRefusedNamingTheField) {
  v1::SubmitJobRequest nan_goal;
  nan_goal.mutable_goal()->set_map_id("store");
  nan_goal.mutable_goal()->mutable_goal()->set_x_m(std::nan(""));
  EXPECT_THAT(FromProto(nan_goal).status().message(), HasSubstr("goal.goal"));
  v1::SubmitJobRequest bad_policy;
  bad_policy.set_route_name("r");
  bad_policy.set_on_robot_lost(static_cast<v1::RequeuePolicy>(77));
  EXPECT_EQ(FromProto(bad_policy).status().code(), absl::StatusCode::kInvalidArgument);
}

TEST(JobRequestConvertTest, AListingFiltersByStateAndRobotAPageAtATime) {
  v1::ListJobsRequest request;
  request.add_states(v1::JOB_STATE_QUEUED);
  request.add_states(v1::JOB_STATE_RUNNING);
  request.set_robot_id("omni1");
  request.set_page_size(4'000'000'000u);
  request.set_page_token("next");
  const absl::StatusOr<JobFilter> filter = FromProto(request);
  ASSERT_TRUE(filter.ok()) << filter.status();
  EXPECT_THAT(filter->states, ElementsAre(JobState::kQueued, JobState::kRunning));
  EXPECT_EQ(filter->robot_id, "omni1");
  EXPECT_EQ(filter->page_size, 1 << 30);
  EXPECT_EQ(filter->page_token, "next");
  request.add_states(v1::JOB_STATE_UNSPECIFIED);
  EXPECT_THAT(FromProto(request).status().message(), HasSubstr("states: unspecified"));
}

}  // namespace
}  // namespace fleetnav
