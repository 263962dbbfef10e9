// Marker sets, routes and jobs over real loopback gRPC against a real SQLite file: success
// paths, idempotency, paging, cancellation, and bad input refused with nothing stored.
#include <gmock/gmock.h>

#include <algorithm>

#include "fleet_fixture.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/proto/job_convert.hpp"
#include "fleetnav/proto/telemetry_convert.hpp"
#include "fleetnav/v1/agent_service.grpc.pb.h"

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

class JobServiceTest : public testing::FleetServerFixture {
 protected:
  void SetUp() override {
    FleetServerFixture::SetUp();
    PutBarn();
  }

  int RouteCount() {
    grpc::ClientContext context;
    v1::ListRoutesResponse response;
    EXPECT_TRUE(fleet_->ListRoutes(&context, {}, &response).ok());
    return response.routes_size();
  }

  int JobCount() {
    grpc::ClientContext context;
    v1::ListJobsRequest request;
    request.set_page_size(1000);
    v1::ListJobsResponse response;
    EXPECT_TRUE(fleet_->ListJobs(&context, request, &response).ok());
    return response.jobs_size();
  }
};

TEST_F(JobServiceTest, MarkerSetsAreVersionedPerMapAndNeedTheirMap) {
  grpc::ClientContext context;
  v1::GetMarkerSetRequest get;
  get.set_map_id("barn");
  v1::GetMarkerSetResponse markers;
  ASSERT_TRUE(fleet_->GetMarkerSet(&context, get, &markers).ok());
  EXPECT_EQ(markers.version(), 1u);
  // The barn's three calibration markers and the 19 straight pieces of its nine stripes, which
  // keep their stripe numbers through the wire.
  EXPECT_EQ(markers.marker_set().markers_size(), 3 + 19);
  int charger_pieces = 0;
  for (const v1::StripeMarker& m : markers.marker_set().markers()) {
    if (m.kind() == v1::MARKER_KIND_CHARGER_STRIPE) {
      ++charger_pieces;
      EXPECT_EQ(m.stripe_id(), 9);
    }
  }
  EXPECT_EQ(charger_pieces, 1);

  grpc::ClientContext unknown_context;
  v1::PutMarkerSetRequest put;
  put.mutable_marker_set()->set_map_id("nowhere");
  v1::PutMarkerSetResponse response;
  const grpc::Status status = fleet_->PutMarkerSet(&unknown_context, put, &response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_THAT(status.error_message(), HasSubstr("nowhere"));
}

TEST_F(JobServiceTest, RoutesAreValidatedAgainstMapAndMarkers) {
  ASSERT_TRUE(PutRoute(StraightRoute("alley", 3.0)).ok());
  EXPECT_EQ(RouteCount(), 1);

  Route unknown_marker = StraightRoute("bad-marker", 3.0);
  unknown_marker.actions.push_back(
      RouteAction{StraightAction{2.0, 0.2}, EndCondition{EndConditionKind::kMarkerDetected, 42}});
  Route inside_obstacle = StraightRoute("bad-goal", 3.0);
  inside_obstacle.actions.push_back(
      RouteAction{FreeNavigationAction{{}, Pose2(11.0, 0.0, 0.0), 0.25},
                  EndCondition{EndConditionKind::kGoalReached, 0}});  // the feed kitchen
  Route outside_map = StraightRoute("bad-waypoint", 3.0);
  outside_map.actions.push_back(
      RouteAction{FreeNavigationAction{{Eigen::Vector2d(40, 0)}, Pose2(0, 0, 0), 0.25},
                  EndCondition{EndConditionKind::kGoalReached, 0}});
  Route unknown_map = StraightRoute("bad-map", 3.0);
  unknown_map.map_id = "nowhere";

  for (const auto& [route, code, text] :
       std::vector<std::tuple<Route, grpc::StatusCode, std::string>>{
           {unknown_marker, grpc::StatusCode::INVALID_ARGUMENT, "actions[1]"},
           {inside_obstacle, grpc::StatusCode::INVALID_ARGUMENT, "actions[1]"},
           {outside_map, grpc::StatusCode::INVALID_ARGUMENT, "outside the map"},
           {unknown_map, grpc::StatusCode::NOT_FOUND, "nowhere"}}) {
    SCOPED_TRACE(route.name);
    const grpc::Status status = PutRoute(route);
    EXPECT_EQ(status.error_code(), code);
    EXPECT_THAT(status.error_message(), HasSubstr(text));
  }
  // A zero-length action is refused when the wire message is converted.
  Route zero = StraightRoute("zero", 0.0);
  const grpc::Status status = PutRoute(zero);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("actions[0]"));
  EXPECT_EQ(RouteCount(), 1);
}

// Trolleys travel with the marker set: a dock action must name one that stands on the map.
TEST_F(JobServiceTest, TrolleyDocksMustNameATrolleyOfTheMap) {
  MarkerSet markers = sim::MarkerSetOf(Barn(), "barn");
  markers.trolleys.push_back({"cart-1", Pose2(2.0, 1.0, 0.0), Eigen::Vector2d(1.0, 0.7), 0.02});
  grpc::ClientContext context;
  v1::PutMarkerSetRequest put;
  *put.mutable_marker_set() = ToProto(markers);
  v1::PutMarkerSetResponse response;
  ASSERT_TRUE(fleet_->PutMarkerSet(&context, put, &response).ok());

  Route known = StraightRoute("dock-known", 3.0);
  known.actions.push_back(RouteAction{DockAction{DockTarget::kTrolley, "cart-1"},
                                      EndCondition{EndConditionKind::kGoalReached, 0}});
  EXPECT_TRUE(PutRoute(known).ok());
  Route unknown = StraightRoute("dock-unknown", 3.0);
  unknown.actions.push_back(RouteAction{DockAction{DockTarget::kTrolley, "cart-9"},
                                        EndCondition{EndConditionKind::kGoalReached, 0}});
  const grpc::Status status = PutRoute(unknown);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("actions[1] (dock): unknown trolley 'cart-9'"));
  EXPECT_EQ(RouteCount(), 1);
}

TEST_F(JobServiceTest, DeletingAMapInUseIsRefused) {
  ASSERT_TRUE(PutRoute(StraightRoute("alley", 3.0)).ok());
  grpc::ClientContext context;
  v1::DeleteMapRequest request;
  request.set_map_id("barn");
  v1::DeleteMapResponse response;
  const grpc::Status status = fleet_->DeleteMap(&context, request, &response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_THAT(status.error_message(), HasSubstr("route"));
  grpc::ClientContext get_context;
  v1::GetMapRequest get;
  get.set_map_id("barn");
  v1::GetMapResponse map;
  EXPECT_TRUE(fleet_->GetMap(&get_context, get, &map).ok());
}

TEST_F(JobServiceTest, SubmitIsIdempotentOnItsKey) {
  ASSERT_TRUE(PutRoute(StraightRoute("alley", 3.0)).ok());
  v1::SubmitJobResponse first, second, third;
  ASSERT_TRUE(Submit("alley", "order-17", &first).ok());
  EXPECT_FALSE(first.deduplicated());
  EXPECT_EQ(first.job().state(), v1::JOB_STATE_QUEUED);
  EXPECT_EQ(first.job().route_version(), 1u);
  ASSERT_TRUE(Submit("alley", "order-17", &second).ok());
  EXPECT_TRUE(second.deduplicated());
  EXPECT_EQ(second.job().job_id(), first.job().job_id());
  ASSERT_TRUE(Submit("alley", "", &third).ok());
  EXPECT_NE(third.job().job_id(), first.job().job_id());
  EXPECT_EQ(JobCount(), 2);
}

TEST_F(JobServiceTest, BadSubmissionsAreRefusedAndNothingIsStored) {
  ASSERT_TRUE(PutRoute(StraightRoute("alley", 3.0)).ok());
  v1::SubmitJobResponse response;
  grpc::Status status = Submit("no-such-route", "", &response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_THAT(status.error_message(), HasSubstr("no-such-route"));

  grpc::ClientContext neither_context;
  status = fleet_->SubmitJob(&neither_context, v1::SubmitJobRequest{}, &response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("target"));

  grpc::ClientContext nan_context;
  v1::SubmitJobRequest nan_goal;
  nan_goal.mutable_goal()->set_map_id("barn");
  nan_goal.mutable_goal()->mutable_goal()->set_x_m(std::numeric_limits<double>::quiet_NaN());
  status = fleet_->SubmitJob(&nan_context, nan_goal, &response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("goal"));

  grpc::ClientContext robot_context;
  v1::SubmitJobRequest unknown_robot;
  unknown_robot.set_route_name("alley");
  unknown_robot.set_robot_id("ghost");
  status = fleet_->SubmitJob(&robot_context, unknown_robot, &response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND);

  grpc::ClientContext policy_context;
  v1::SubmitJobRequest bad_policy;
  bad_policy.set_route_name("alley");
  bad_policy.set_on_robot_lost(static_cast<v1::RequeuePolicy>(9));
  status = fleet_->SubmitJob(&policy_context, bad_policy, &response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("on_robot_lost"));
  EXPECT_EQ(JobCount(), 0);
}

TEST_F(JobServiceTest, ListJobsPagesAndFilters) {
  ASSERT_TRUE(PutRoute(StraightRoute("alley", 3.0)).ok());
  for (int i = 0; i < 5; ++i) {
    v1::SubmitJobResponse response;
    ASSERT_TRUE(Submit("alley", "k" + std::to_string(i), &response).ok());
  }
  std::vector<std::string> seen;
  std::string token;
  do {
    grpc::ClientContext context;
    v1::ListJobsRequest request;
    request.set_page_size(2);
    request.set_page_token(token);
    v1::ListJobsResponse page;
    ASSERT_TRUE(fleet_->ListJobs(&context, request, &page).ok());
    EXPECT_LE(page.jobs_size(), 2);
    for (const auto& job : page.jobs()) seen.push_back(job.job_id());
    token = page.next_page_token();
  } while (!token.empty());
  EXPECT_EQ(seen.size(), 5u);
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));

  grpc::ClientContext filter_context;
  v1::ListJobsRequest cancelled_only;
  cancelled_only.add_states(v1::JOB_STATE_CANCELLED);
  v1::ListJobsResponse none;
  ASSERT_TRUE(fleet_->ListJobs(&filter_context, cancelled_only, &none).ok());
  EXPECT_EQ(none.jobs_size(), 0);

  grpc::ClientContext bad_context;
  v1::ListJobsRequest bad;
  bad.set_page_token("xyz");
  EXPECT_EQ(fleet_->ListJobs(&bad_context, bad, &none).error_code(),
            grpc::StatusCode::INVALID_ARGUMENT);
  grpc::ClientContext state_context;
  v1::ListJobsRequest bad_state;
  bad_state.add_states(static_cast<v1::JobState>(42));
  EXPECT_EQ(fleet_->ListJobs(&state_context, bad_state, &none).error_code(),
            grpc::StatusCode::INVALID_ARGUMENT);
}

TEST_F(JobServiceTest, CancelEndsAQueuedJobOnceAndWatchJobReplaysItsEvents) {
  ASSERT_TRUE(PutRoute(StraightRoute("alley", 3.0)).ok());
  v1::SubmitJobResponse submitted;
  ASSERT_TRUE(Submit("alley", "", &submitted).ok());
  grpc::ClientContext context;
  v1::CancelJobRequest cancel;
  cancel.set_job_id(submitted.job().job_id());
  cancel.set_reason("operator changed plans");
  v1::CancelJobResponse cancelled;
  ASSERT_TRUE(fleet_->CancelJob(&context, cancel, &cancelled).ok());
  EXPECT_EQ(cancelled.job().state(), v1::JOB_STATE_CANCELLED);

  grpc::ClientContext again_context;
  const grpc::Status again = fleet_->CancelJob(&again_context, cancel, &cancelled);
  EXPECT_EQ(again.error_code(), grpc::StatusCode::FAILED_PRECONDITION);

  grpc::ClientContext watch_context;
  v1::WatchJobRequest watch;
  watch.set_job_id(submitted.job().job_id());
  auto reader = fleet_->WatchJob(&watch_context, watch);
  std::vector<v1::JobEventType> types;
  v1::JobEvent event;
  while (reader->Read(&event)) types.push_back(event.type());
  EXPECT_TRUE(reader->Finish().ok());  // the stream ends with the job
  // QUEUED (perhaps again, with why it waits), then CANCELLED.
  types.erase(std::unique(types.begin(), types.end()), types.end());
  EXPECT_THAT(types,
              ::testing::ElementsAre(v1::JOB_EVENT_TYPE_QUEUED, v1::JOB_EVENT_TYPE_CANCELLED));

  grpc::ClientContext unknown_context;
  cancel.set_job_id("job-999999");
  EXPECT_EQ(fleet_->CancelJob(&unknown_context, cancel, &cancelled).error_code(),
            grpc::StatusCode::NOT_FOUND);
}

}  // namespace
}  // namespace fleetnav

namespace fleetnav {
namespace {

TEST_F(JobServiceTest, GetRouteReturnsTheLatestVersionAndUnknownIsNotFound) {
  ASSERT_TRUE(PutRoute(StraightRoute("alley", 3.0)).ok());
  ASSERT_TRUE(PutRoute(StraightRoute("alley", 4.0)).ok());
  grpc::ClientContext context;
  v1::GetRouteRequest request;
  request.set_name("alley");
  v1::GetRouteResponse response;
  ASSERT_TRUE(fleet_->GetRoute(&context, request, &response).ok());
  EXPECT_EQ(response.version(), 2u);
  ASSERT_EQ(response.route().actions_size(), 1);
  EXPECT_DOUBLE_EQ(response.route().actions(0).straight().distance_m(), 4.0);

  grpc::ClientContext unknown_context;
  request.set_name("nowhere");
  const grpc::Status status = fleet_->GetRoute(&unknown_context, request, &response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND);
  grpc::ClientContext bad_context;
  request.set_name("bad name!");
  EXPECT_EQ(fleet_->GetRoute(&bad_context, request, &response).error_code(),
            grpc::StatusCode::INVALID_ARGUMENT);
}

TEST_F(JobServiceTest, ListRobotsIsEmptyUntilARobotConnects) {
  grpc::ClientContext context;
  v1::ListRobotsResponse response;
  ASSERT_TRUE(fleet_->ListRobots(&context, {}, &response).ok());
  EXPECT_EQ(response.robots_size(), 0);
}

TEST_F(JobServiceTest, JobsNoRobotCanDriveDoNotHoldBackOneARobotCan) {
  ASSERT_TRUE(PutRoute(StraightRoute("short", 0.3)).ok());
  Route fence = StraightRoute("fence", 1.0);
  fence.actions[0] = RouteAction{FenceNavigationAction{Side::kLeft, 0.5, 5.0, 0.25}, {}};
  ASSERT_TRUE(PutRoute(fence).ok());
  v1::SubmitJobResponse response;
  for (int i = 0; i < 20; ++i) {  // ahead of the drivable job by priority and by age
    ASSERT_TRUE(Submit("fence", "fence-" + std::to_string(i), &response, /*priority=*/9).ok());
  }
  v1::SubmitJobResponse drivable;
  ASSERT_TRUE(Submit("short", "short", &drivable, /*priority=*/0).ok());

  auto agents = v1::AgentService::NewStub(channel_);
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(20));
  auto stream = agents->Connect(&context);
  v1::AgentMessage hello;
  *hello.mutable_hello() = ToProto(RobotIdentity{"lely1", LelyVectorModel(), {"straight"}, "t"});
  ASSERT_TRUE(stream->Write(hello));
  v1::ServerMessage message;
  ASSERT_TRUE(stream->Read(&message) && message.has_welcome());
  while (stream->Read(&message) && !message.has_assignment()) {
  }
  ASSERT_TRUE(message.has_assignment());
  EXPECT_EQ(message.assignment().job().job_id(), drivable.job().job_id());
  context.TryCancel();
  (void)stream->Finish();
}

v1::PlanPathsRequest::Agent PlanAgent(const std::string& id, double sx, double sy, double gx,
                                      double gy, const std::string& kind = "lely-vector") {
  v1::PlanPathsRequest::Agent agent;
  agent.set_robot_id(id);
  agent.set_kind_name(kind);
  agent.mutable_start()->set_x_m(sx);
  agent.mutable_start()->set_y_m(sy);
  agent.mutable_goal()->set_x_m(gx);
  agent.mutable_goal()->set_y_m(gy);
  return agent;
}

// PlanPaths on the barn for two Lely robots; fails the test unless the call succeeds.
v1::PlanPathsResponse PlanTwoOnTheBarn(v1::FleetService::Stub& fleet,
                                       const v1::PlanPathsRequest::Agent& first,
                                       const v1::PlanPathsRequest::Agent& second) {
  grpc::ClientContext context;
  v1::PlanPathsRequest request;
  request.set_map_id("barn");
  request.set_time_limit_s(20.0);  // a safety net: the kinematic planner's budget is work
  *request.add_agents() = first;
  *request.add_agents() = second;
  v1::PlanPathsResponse response;
  const grpc::Status status = fleet.PlanPaths(&context, request, &response);
  EXPECT_TRUE(status.ok()) << status.error_message();
  return response;
}

TEST_F(JobServiceTest, PlanPathsSwapsTwoRobotsInTheAlleyWithoutMeeting) {
  const v1::PlanPathsResponse response = PlanTwoOnTheBarn(
      *fleet_, PlanAgent("lely1", -6.0, 0.0, 6.0, 0.0), PlanAgent("lely2", 6.0, 0.0, -6.0, 0.0));
  ASSERT_EQ(response.paths_size(), 2);
  const auto& a = response.paths(0).poses();
  const auto& b = response.paths(1).poses();
  EXPECT_NEAR(a[a.size() - 1].pose().x_m(), 6.0, 1e-9);
  EXPECT_NEAR(b[b.size() - 1].pose().x_m(), -6.0, 1e-9);
  // At every planned time the robots are more than one planning cell apart or waiting apart.
  for (int t = 1; t + 1 < std::min(a.size(), b.size()); ++t) {
    const double dx = a[t].pose().x_m() - b[t].pose().x_m();
    const double dy = a[t].pose().y_m() - b[t].pose().y_m();
    EXPECT_GT(std::hypot(dx, dy), 1.0) << "at step " << t;
  }
  EXPECT_GT(response.dependencies_size(), 0);  // someone passes where the other has been
  EXPECT_GT(response.makespan_s(), 12.0 / 0.5 - 1e-9);
}

TEST_F(JobServiceTest, PlanPathsKeepsTheLelyFacingForwardAndApartFromTheStorePlatform) {
  // A Lely and a mecanum platform swap ends of the barn alley. The Lely has a heading and must
  // never reverse; the plan comes from the kinematic planner.
  const v1::PlanPathsResponse response =
      PlanTwoOnTheBarn(*fleet_, PlanAgent("lely1", -6.0, 0.0, 6.0, 0.0),
                       PlanAgent("cart1", 6.0, 0.0, -6.0, 0.0, "mecanum-platform"));
  ASSERT_EQ(response.paths_size(), 2);
  EXPECT_EQ(response.solver(), "kinematic");
  const auto& lely = response.paths(0).poses();
  const auto& cart = response.paths(1).poses();
  EXPECT_NEAR(lely[lely.size() - 1].pose().x_m(), 6.0, 1e-9);
  EXPECT_NEAR(cart[cart.size() - 1].pose().x_m(), -6.0, 1e-9);
  // Between planned poses the Lely moves along the yaw it had (forward), or turns in place.
  for (int t = 1; t + 1 < lely.size(); ++t) {
    const double dx = lely[t].pose().x_m() - lely[t - 1].pose().x_m();
    const double dy = lely[t].pose().y_m() - lely[t - 1].pose().y_m();
    if (std::hypot(dx, dy) < 1e-9) continue;
    const double yaw = lely[t - 1].pose().yaw_rad();
    EXPECT_GT(dx * std::cos(yaw) + dy * std::sin(yaw), 0.0) << "step " << t;
  }
  // Footprints (circumscribed discs) never overlap at a planned time.
  const double clearance_m = RobotModelByKind("lely-vector")->CircumscribedRadius() +
                             RobotModelByKind("mecanum-platform")->CircumscribedRadius();
  for (int t = 1; t + 1 < std::min(lely.size(), cart.size()); ++t) {
    const double d = std::hypot(lely[t].pose().x_m() - cart[t].pose().x_m(),
                                lely[t].pose().y_m() - cart[t].pose().y_m());
    EXPECT_GE(d, clearance_m - 1e-9) << "step " << t;
  }
  EXPECT_GT(response.dependencies_size(), 0);
}

TEST_F(JobServiceTest, PlanPathsSendsTheSecondRobotForOneGoalBesideIt) {
  const v1::PlanPathsResponse response = PlanTwoOnTheBarn(
      *fleet_, PlanAgent("lely1", -2.0, 0.0, 2.0, 0.0), PlanAgent("lely2", 6.0, 0.0, 2.0, 0.0));
  ASSERT_EQ(response.paths_size(), 2);
  const auto& near = response.paths(1).poses();  // lely2 is 4 m away, lely1 4 m too: index wins
  const auto& first = response.paths(0).poses();
  EXPECT_NEAR(first[first.size() - 1].pose().x_m(), 2.0, 1e-9);
  const double dx = near[near.size() - 1].pose().x_m() - 2.0;
  const double dy = near[near.size() - 1].pose().y_m();
  // On the planning cell next to the goal's (cells are twice the Lely's circumscribed radius),
  // on its own side of the alley.
  EXPECT_GT(std::hypot(dx, dy), 0.5);
  EXPECT_LE(std::hypot(dx, dy), 2.0 * response.cell_size_m() + 1e-9);
  EXPECT_GT(dx, 0.0);
  EXPECT_FALSE(response.paths(0).waits_beside_goal());
  EXPECT_TRUE(response.paths(1).waits_beside_goal());
}

TEST_F(JobServiceTest, PlanPathsRefusesBadAgentsNamingThem) {
  struct Case {
    v1::PlanPathsRequest request;
    grpc::StatusCode code;
    std::string text;
  };
  std::vector<Case> cases(4);
  cases[0].request.set_map_id("barn");
  *cases[0].request.add_agents() = PlanAgent("lely1", 11.0, 0.0, 0.0, 0.0);  // feed kitchen
  cases[0].code = grpc::StatusCode::INVALID_ARGUMENT;
  cases[0].text = "agents[0].start";
  cases[1].request.set_map_id("barn");
  *cases[1].request.add_agents() = PlanAgent("lely1", -6.0, 0.0, 0.0, 0.0);
  cases[1].request.mutable_agents(0)->set_kind_name("hovercraft");
  cases[1].code = grpc::StatusCode::INVALID_ARGUMENT;
  cases[1].text = "kind_name";
  cases[2].request.set_map_id("nowhere");
  *cases[2].request.add_agents() = PlanAgent("lely1", -6.0, 0.0, 0.0, 0.0);
  cases[2].code = grpc::StatusCode::NOT_FOUND;
  cases[2].text = "nowhere";
  cases[3].request.set_map_id("barn");
  cases[3].code = grpc::StatusCode::INVALID_ARGUMENT;
  cases[3].text = "agents";
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    grpc::ClientContext context;
    v1::PlanPathsResponse response;
    const grpc::Status status = fleet_->PlanPaths(&context, c.request, &response);
    EXPECT_EQ(status.error_code(), c.code);
    EXPECT_THAT(status.error_message(), ::testing::HasSubstr(c.text));
  }
}

}  // namespace
}  // namespace fleetnav
