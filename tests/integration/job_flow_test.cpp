// A job end to end over real loopback gRPC: fleetnavd dispatches it to a simulated robot's
// agent, the agent drives it in the ODE barn, and the job's events and end state come back.
#include <gmock/gmock.h>

#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "fleet_fixture.hpp"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/localization/dead_reckoning_localizer.hpp"
#include "fleetnav/localization/samcl_localizer.hpp"
#include "fleetnav/proto/geometry_convert.hpp"
#include "fleetnav/proto/telemetry_convert.hpp"
#include "fleetnav/robot_agent/agent.hpp"
#include "fleetnav/robot_agent/fleet_site_source.hpp"
#include "fleetnav/robot_agent/server_link.hpp"
#include "fleetnav/robot_agent/sim_hal.hpp"
#include "fleetnav/sim/sim_server.hpp"

namespace fleetnav {
namespace {

class JobFlowTest : public testing::FleetServerFixture {
 protected:
  server::FleetServerParams Params() override {
    server::FleetServerParams params = FleetServerFixture::Params();
    params.jobs.lost_robot_timeout_s = 0.5;
    params.jobs.charging_routes = {{"hall", "hall-charge"}};
    return params;
  }

  void StartSimulator() {
    sim::SimServerParams params;
    params.listen_address = "127.0.0.1:0";
    params.simulation.seed = 3;
    simulator_ = std::make_unique<sim::SimServer>(Barn(), params);
    absl::StatusOr<int> port = simulator_->Start();
    ASSERT_TRUE(port.ok()) << port.status();
    sim_port_ = *port;
  }

  /// Runs an agent in job mode on a thread until it has ended `jobs` jobs. With `sites`, each
  /// job's map and marker set come from fleetnavd and SAMCL runs on them; `sites_loaded`
  /// then lists the map versions and marker-set versions the agent localized on.
  std::thread StartAgent(int jobs, agent::AgentResult* result, bool sites = false,
                         std::vector<std::pair<uint32_t, uint32_t>>* sites_loaded = nullptr) {
    return std::thread([this, jobs, result, sites, sites_loaded] {
      const RobotModel model = LelyVectorModel();
      // Without sites the robot says it turns and drives straight only (the dispatcher's
      // capability test below relies on a route it cannot drive).
      const std::vector<std::string> capabilities =
          sites ? agent::SupportedActionTypes(model) : std::vector<std::string>{"straight", "turn"};
      agent::ServerLink link(channel_, RobotIdentity{"lely1", model, capabilities, "t"});
      agent::FleetSiteSource site_source(channel_);
      agent::SimHal hal(grpc::CreateChannel("127.0.0.1:" + std::to_string(sim_port_),
                                            grpc::InsecureChannelCredentials()),
                        "lely1");
      agent::AgentParams params;
      params.max_jobs = jobs;
      localization::DeadReckoningLocalizer localizer =
          localization::DeadReckoningLocalizer::Create(model, Barn().robots[0].pose).value();
      agent::AgentPorts ports{&hal, &localizer, &link, &link};
      if (sites) {
        ports.sites = &site_source;
        ports.make_localizer =
            [&model, sites_loaded](
                const agent::SiteData& site,
                const Pose2& start) -> absl::StatusOr<std::unique_ptr<localization::Localizer>> {
          if (sites_loaded != nullptr) {
            sites_loaded->emplace_back(site.map_version, site.marker_set_version);
          }
          auto samcl = localization::SamclLocalizer::Create(
              model, *site.map, site.markers.value_or(MarkerSet{}), start);
          if (!samcl.ok()) return samcl.status();
          return std::make_unique<localization::SamclLocalizer>(*std::move(samcl));
        };
      }
      agent::Agent agent(agent::RouteContext{model, std::nullopt, nullptr}, ports, std::nullopt,
                         params);
      absl::StatusOr<agent::AgentResult> run = agent.Run();
      link.Close();
      if (run.ok()) *result = *run;
    });
  }

  std::vector<v1::JobEvent> WatchToTheEnd(const std::string& job_id) {
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(60));
    v1::WatchJobRequest request;
    request.set_job_id(job_id);
    auto reader = fleet_->WatchJob(&context, request);
    std::vector<v1::JobEvent> events;
    v1::JobEvent event;
    while (reader->Read(&event)) events.push_back(event);
    EXPECT_TRUE(reader->Finish().ok());
    return events;
  }

  /// Waits (up to 1 s) until fleetnavd shows `robot_id` as `shown` says; false if it never does.
  bool WaitUntilRobot(const std::string& robot_id,
                      const std::function<bool(const v1::RobotState&)>& shown) {
    for (int i = 0; i < 200; ++i) {
      grpc::ClientContext context;
      v1::GetRobotRequest get;
      get.set_robot_id(robot_id);
      v1::GetRobotResponse got;
      if (fleet_->GetRobot(&context, get, &got).ok() && shown(got.robot())) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
  }

  /// A 30 × 20 m hall (0.1 m cells) with a wall along x = 15 m from y = 0 to y = 14 m.
  void PutHall() {
    OccupancyGrid hall = *OccupancyGrid::Filled(300, 200, 0.1, Pose2(), OccupancyGrid::kFreeValue);
    for (int y = 0; y < 140; ++y) {
      for (int x = 148; x < 152; ++x) hall.SetValue({x, y}, OccupancyGrid::kOccupiedValue);
    }
    grpc::ClientContext context;
    v1::PutMapRequest map;
    map.set_map_id("hall");
    *map.mutable_grid() = ToProto(hall);
    v1::PutMapResponse response;
    ASSERT_TRUE(fleet_->PutMap(&context, map, &response).ok());
  }

  std::unique_ptr<sim::SimServer> simulator_;
  int sim_port_ = 0;
};

// In job mode the agent fetches the job's map and marker set from fleetnavd at the versions the
// route was validated against and localizes with SAMCL on them; the robot, judged by the
// simulator's truth, ends where the route says.
TEST_F(JobFlowTest, AgentLocalizesOnTheJobsMapAndMarkersFromTheServer) {
  PutBarn();
  absl::StatusOr<Route> route = LoadRoute(std::string(FLEETNAV_ROUTES_DIR) + "/demo.yaml");
  ASSERT_TRUE(route.ok());
  ASSERT_TRUE(PutRoute(*route).ok());
  StartSimulator();
  agent::AgentResult result;
  std::vector<std::pair<uint32_t, uint32_t>> sites_loaded;
  std::thread agent = StartAgent(/*jobs=*/1, &result, /*sites=*/true, &sites_loaded);
  v1::SubmitJobResponse submitted;
  ASSERT_TRUE(Submit(route->name, "demo-site", &submitted).ok());
  const std::vector<v1::JobEvent> events = WatchToTheEnd(submitted.job().job_id());
  agent.join();
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back().type(), v1::JOB_EVENT_TYPE_SUCCEEDED) << events.back().reason();
  ASSERT_EQ(sites_loaded.size(), 1u);
  EXPECT_EQ(sites_loaded[0], std::make_pair(1u, 1u));  // map barn v1, marker set v1
  const Pose2 nominal = Barn().robots[0].pose * Pose2(5.0, 3.0, kPi / 2);
  const Pose2 truth = simulator_->lockstep().GroundTruth().robots.at(0).pose;
  EXPECT_LT((truth.translation() - nominal.translation()).norm(), 0.2) << truth.DebugString();
  EXPECT_TRUE(result.final_pose_in_map.IsNear(truth, 0.1, DegToRad(3)))
      << result.final_pose_in_map.DebugString() << " vs " << truth.DebugString();
}

TEST_F(JobFlowTest, SubmittedRouteIsDispatchedDrivenAndSucceeds) {
  PutBarn();
  absl::StatusOr<Route> route = LoadRoute(std::string(FLEETNAV_ROUTES_DIR) + "/demo.yaml");
  ASSERT_TRUE(route.ok());
  ASSERT_TRUE(PutRoute(*route).ok());
  StartSimulator();
  agent::AgentResult result;
  std::thread agent = StartAgent(/*jobs=*/1, &result);

  v1::SubmitJobResponse submitted;
  ASSERT_TRUE(Submit(route->name, "demo-1", &submitted).ok());
  const std::vector<v1::JobEvent> events = WatchToTheEnd(submitted.job().job_id());
  agent.join();

  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.front().type(), v1::JOB_EVENT_TYPE_QUEUED);
  EXPECT_EQ(events.back().type(), v1::JOB_EVENT_TYPE_SUCCEEDED) << events.back().reason();
  EXPECT_EQ(events.back().state(), v1::JOB_STATE_SUCCEEDED);
  std::vector<v1::JobEventType> types;
  int actions_started = 0;
  for (const auto& e : events) {
    types.push_back(e.type());
    actions_started += e.type() == v1::JOB_EVENT_TYPE_ACTION_STARTED;
  }
  EXPECT_THAT(types, ::testing::Contains(v1::JOB_EVENT_TYPE_ASSIGNED));
  EXPECT_THAT(types, ::testing::Contains(v1::JOB_EVENT_TYPE_STARTED));
  EXPECT_THAT(types, ::testing::Contains(v1::JOB_EVENT_TYPE_PROGRESS));
  EXPECT_EQ(actions_started, 3);
  EXPECT_EQ(result.jobs_finished, 1);

  grpc::ClientContext context;
  v1::GetJobRequest get;
  get.set_job_id(submitted.job().job_id());
  v1::GetJobResponse job;
  ASSERT_TRUE(fleet_->GetJob(&context, get, &job).ok());
  EXPECT_EQ(job.job().assigned_robot_id(), "lely1");
  EXPECT_DOUBLE_EQ(job.job().progress_fraction(), 1.0);

  const Pose2 nominal = Barn().robots[0].pose * Pose2(5.0, 3.0, kPi / 2);
  const sim::GroundTruthSnapshot truth = simulator_->lockstep().GroundTruth();
  EXPECT_LT((truth.robots[0].pose.translation() - nominal.translation()).norm(), 0.2);
  EXPECT_LT(std::abs(AngleDifference(truth.robots[0].pose.yaw_rad(), nominal.yaw_rad())),
            DegToRad(3.0));
  simulator_->Shutdown();
}

TEST_F(JobFlowTest, JobsGoByPriorityAndARouteTheRobotCannotDriveStaysQueued) {
  PutBarn();
  ASSERT_TRUE(PutRoute(StraightRoute("short", 0.3)).ok());
  Route fence = StraightRoute("fence", 1.0);
  fence.actions[0] = RouteAction{FenceNavigationAction{Side::kLeft, 0.5, 5.0, 0.25}, {}};
  ASSERT_TRUE(PutRoute(fence).ok());
  v1::SubmitJobResponse low, high, unfit;
  ASSERT_TRUE(Submit("fence", "", &unfit, /*priority=*/9).ok());
  ASSERT_TRUE(Submit("short", "", &low, /*priority=*/1).ok());
  ASSERT_TRUE(Submit("short", "", &high, /*priority=*/5).ok());
  StartSimulator();
  agent::AgentResult result;
  std::thread agent = StartAgent(/*jobs=*/2, &result);
  const std::vector<v1::JobEvent> high_events = WatchToTheEnd(high.job().job_id());
  const std::vector<v1::JobEvent> low_events = WatchToTheEnd(low.job().job_id());
  agent.join();
  ASSERT_FALSE(high_events.empty());
  ASSERT_FALSE(low_events.empty());
  EXPECT_EQ(high_events.back().state(), v1::JOB_STATE_SUCCEEDED) << high_events.back().reason();
  EXPECT_EQ(low_events.back().state(), v1::JOB_STATE_SUCCEEDED);
  // The higher priority job was assigned first.
  auto assigned_at = [](const std::vector<v1::JobEvent>& events) {
    for (const auto& e : events) {
      if (e.type() == v1::JOB_EVENT_TYPE_ASSIGNED) return e.unix_ms();
    }
    return int64_t{-1};
  };
  EXPECT_LE(assigned_at(high_events), assigned_at(low_events));
  grpc::ClientContext context;
  v1::GetJobRequest get;
  get.set_job_id(unfit.job().job_id());
  v1::GetJobResponse job;
  ASSERT_TRUE(fleet_->GetJob(&context, get, &job).ok());
  EXPECT_EQ(job.job().state(), v1::JOB_STATE_QUEUED);  // no robot can follow a fence yet
  EXPECT_EQ(job.job().reason(),
            "no robot that has connected can run actions[0] (fence_navigation)");
  simulator_->Shutdown();
}

TEST_F(JobFlowTest, ARobotThatDropsMidJobPausesItAndTheJobFailsAfterTheTimeout) {
  PutBarn();
  ASSERT_TRUE(PutRoute(StraightRoute("long", 8.0)).ok());
  StartSimulator();
  v1::SubmitJobResponse submitted;
  ASSERT_TRUE(Submit("long", "", &submitted).ok());
  {
    // An agent that takes the job, drives a little, then vanishes.
    const RobotModel model = LelyVectorModel();
    agent::ServerLink link(channel_, RobotIdentity{"lely1", model, {"straight"}, "t"});
    agent::SimHal hal(grpc::CreateChannel("127.0.0.1:" + std::to_string(sim_port_),
                                          grpc::InsecureChannelCredentials()),
                      "lely1");
    for (int tick = 0; tick < 2000; ++tick) {
      absl::StatusOr<std::optional<SensorFrame>> frame = hal.NextFrame();
      ASSERT_TRUE(frame.ok() && frame->has_value());
      ActuatorCommand command;
      command.tick = (*frame)->tick;
      ASSERT_TRUE(hal.Send(command).ok());
      if (std::optional<JobAssignment> assignment = link.TakeAssignment()) {
        link.SetCurrentJob(assignment->job.job_id);
        JobEvent started;
        started.job_id = assignment->job.job_id;
        started.type = JobEventType::kActionStarted;
        started.action_index = 0;
        link.ReportEvent(started);
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    link.Close();
  }
  const std::vector<v1::JobEvent> events = WatchToTheEnd(submitted.job().job_id());
  std::vector<v1::JobEventType> types;
  for (const auto& e : events) types.push_back(e.type());
  EXPECT_THAT(types, ::testing::Contains(v1::JOB_EVENT_TYPE_PAUSED));
  EXPECT_EQ(types.back(), v1::JOB_EVENT_TYPE_FAILED);
  EXPECT_THAT(events.back().reason(), ::testing::HasSubstr("lost"));
  simulator_->Shutdown();
}

}  // namespace
}  // namespace fleetnav

namespace fleetnav {
namespace {

using AgentStream = grpc::ClientReaderWriter<v1::AgentMessage, v1::ServerMessage>;

v1::AgentMessage HelloFor(const std::string& robot_id, const std::string& resume_job_id) {
  v1::AgentMessage hello;
  *hello.mutable_hello() =
      ToProto(RobotIdentity{robot_id, LelyVectorModel(), {"straight"}, "test"});
  hello.mutable_hello()->set_resume_job_id(resume_job_id);
  return hello;
}

v1::AgentMessage EventFor(const std::string& job_id, v1::AgentEvent::Type type) {
  v1::AgentMessage message;
  message.mutable_event()->set_type(type);
  message.mutable_event()->set_job_id(job_id);
  return message;
}

TEST_F(JobFlowTest, ARobotThatReconnectsWithItsJobResumesIt) {
  PutBarn();
  ASSERT_TRUE(PutRoute(StraightRoute("long", 8.0)).ok());
  v1::SubmitJobResponse submitted;
  ASSERT_TRUE(Submit("long", "", &submitted).ok());
  const std::string job_id = submitted.job().job_id();
  auto agents = v1::AgentService::NewStub(channel_);
  auto job_state = [&] {
    grpc::ClientContext context;
    v1::GetJobRequest get;
    get.set_job_id(job_id);
    v1::GetJobResponse job;
    EXPECT_TRUE(fleet_->GetJob(&context, get, &job).ok());
    return job.job().state();
  };
  auto wait_for = [&](v1::JobState state) {
    for (int i = 0; i < 200 && job_state() != state; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return job_state();
  };
  {
    grpc::ClientContext context;
    std::unique_ptr<AgentStream> stream = agents->Connect(&context);
    ASSERT_TRUE(stream->Write(HelloFor("lely1", "")));
    v1::ServerMessage message;
    ASSERT_TRUE(stream->Read(&message));  // welcome
    ASSERT_TRUE(stream->Read(&message));  // the assignment
    ASSERT_TRUE(message.has_assignment());
    EXPECT_EQ(message.assignment().job().job_id(), job_id);
    ASSERT_TRUE(stream->Write(EventFor(job_id, v1::AgentEvent::TYPE_ACTION_STARTED)));
    EXPECT_EQ(wait_for(v1::JOB_STATE_RUNNING), v1::JOB_STATE_RUNNING);
    stream->WritesDone();
    (void)stream->Finish();
  }
  EXPECT_EQ(wait_for(v1::JOB_STATE_PAUSED), v1::JOB_STATE_PAUSED);

  grpc::ClientContext context;
  std::unique_ptr<AgentStream> stream = agents->Connect(&context);
  ASSERT_TRUE(stream->Write(HelloFor("lely1", job_id)));
  v1::ServerMessage welcome;
  ASSERT_TRUE(stream->Read(&welcome));
  EXPECT_EQ(job_state(), v1::JOB_STATE_RUNNING);  // resumed before the welcome was sent
  ASSERT_TRUE(stream->Write(EventFor(job_id, v1::AgentEvent::TYPE_JOB_SUCCEEDED)));
  EXPECT_EQ(wait_for(v1::JOB_STATE_SUCCEEDED), v1::JOB_STATE_SUCCEEDED);
  const std::vector<v1::JobEvent> events = WatchToTheEnd(job_id);
  std::vector<v1::JobEventType> types;
  for (const auto& e : events) types.push_back(e.type());
  EXPECT_THAT(types, ::testing::IsSupersetOf({v1::JOB_EVENT_TYPE_PAUSED, v1::JOB_EVENT_TYPE_RESUMED,
                                              v1::JOB_EVENT_TYPE_SUCCEEDED}));
  stream->WritesDone();
  (void)stream->Finish();
}

// A robot whose agent restarted comes back without its job: fleetnavd sends the job again,
// beginning where the robot's last telemetry placed it (action and fraction of it done), and
// the job runs on instead of failing or starting over.
TEST_F(JobFlowTest, ARobotWhoseAgentRestartedGetsItsJobAgainFromWhereItWas) {
  PutBarn();
  ASSERT_TRUE(PutRoute(StraightRoute("long", 8.0)).ok());
  v1::SubmitJobResponse submitted;
  ASSERT_TRUE(Submit("long", "", &submitted).ok());
  const std::string job_id = submitted.job().job_id();
  auto agents = v1::AgentService::NewStub(channel_);
  {
    grpc::ClientContext context;
    std::unique_ptr<AgentStream> stream = agents->Connect(&context);
    ASSERT_TRUE(stream->Write(HelloFor("lely1", "")));
    v1::ServerMessage message;
    ASSERT_TRUE(stream->Read(&message));  // welcome
    ASSERT_TRUE(stream->Read(&message));  // the assignment, from the beginning
    ASSERT_TRUE(message.has_assignment());
    EXPECT_EQ(message.assignment().resume_action_index(), 0);
    EXPECT_EQ(message.assignment().resume_action_fraction(), 0.0);
    ASSERT_TRUE(stream->Write(EventFor(job_id, v1::AgentEvent::TYPE_ACTION_STARTED)));
    Telemetry telemetry;
    telemetry.stamp_ns = 1;
    telemetry.sequence = 1;
    telemetry.job_id = job_id;
    telemetry.action_index = 0;
    telemetry.action_progress_fraction = 0.45;
    telemetry.job_progress_fraction = 0.45;
    v1::AgentMessage wire;
    *wire.mutable_telemetry() = ToProto(telemetry);
    ASSERT_TRUE(stream->Write(wire));
    // The telemetry has been taken once the robot shows it.
    EXPECT_TRUE(WaitUntilRobot("lely1", [](const v1::RobotState& robot) {
      return robot.last_telemetry().action_progress_fraction() > 0.4;
    }));
    context.TryCancel();  // the agent dies: no goodbye
    (void)stream->Finish();
  }
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(20));
  std::unique_ptr<AgentStream> stream = agents->Connect(&context);
  ASSERT_TRUE(stream->Write(HelloFor("lely1", "")));  // a fresh agent: no job
  v1::ServerMessage message;
  ASSERT_TRUE(stream->Read(&message));  // welcome
  ASSERT_TRUE(stream->Read(&message));
  ASSERT_TRUE(message.has_assignment()) << message.DebugString();
  EXPECT_EQ(message.assignment().job().job_id(), job_id);
  EXPECT_EQ(message.assignment().resume_action_index(), 0);
  EXPECT_DOUBLE_EQ(message.assignment().resume_action_fraction(), 0.45);
  ASSERT_TRUE(stream->Write(EventFor(job_id, v1::AgentEvent::TYPE_JOB_SUCCEEDED)));
  const std::vector<v1::JobEvent> events = WatchToTheEnd(job_id);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back().type(), v1::JOB_EVENT_TYPE_SUCCEEDED);
  bool resumed = false;
  for (const auto& e : events) {
    resumed |= e.type() == v1::JOB_EVENT_TYPE_RESUMED &&
               e.reason().find("sent again from action 0, 45 % of it done") != std::string::npos;
  }
  EXPECT_TRUE(resumed);
  context.TryCancel();  // the clearances sent after the assignment are left unread
  (void)stream->Finish();
}

// The dispatcher ranks robots by the path they would drive over the map, not the straight line:
// a robot 6 m from the goal but behind a 14 m wall (about 22 m to drive) loses to one 12 m away
// in the open.
TEST_F(JobFlowTest, TheRobotWithTheShortestPathOverTheMapGetsTheJob) {
  PutHall();
  auto agents = v1::AgentService::NewStub(channel_);
  struct Robot {
    std::string id;
    Pose2 pose;
    grpc::ClientContext context;
    std::unique_ptr<AgentStream> stream;
  };
  std::vector<std::unique_ptr<Robot>> robots;
  for (const auto& [id, pose] : {std::pair<std::string, Pose2>{"behind-wall", Pose2(12, 4, 0)},
                                 std::pair<std::string, Pose2>{"in-the-open", Pose2(27, 12, 0)}}) {
    auto robot = std::make_unique<Robot>();
    robot->id = id;
    robot->pose = pose;
    robot->context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(20));
    robot->stream = agents->Connect(&robot->context);
    v1::AgentMessage hello;
    *hello.mutable_hello() =
        ToProto(RobotIdentity{id, LelyVectorModel(), {"free_navigation"}, "test"});
    ASSERT_TRUE(robot->stream->Write(hello));
    v1::ServerMessage welcome;
    ASSERT_TRUE(robot->stream->Read(&welcome));
    Telemetry telemetry;
    telemetry.stamp_ns = 1;
    telemetry.sequence = 1;
    telemetry.pose_in_map = pose;
    v1::AgentMessage wire;
    *wire.mutable_telemetry() = ToProto(telemetry);
    ASSERT_TRUE(robot->stream->Write(wire));
    robots.push_back(std::move(robot));
  }
  // Both poses are known before the job is submitted.
  for (const auto& robot : robots) {
    EXPECT_TRUE(WaitUntilRobot(
        robot->id, [](const v1::RobotState& shown) { return shown.has_last_telemetry(); }));
  }
  grpc::ClientContext context;
  v1::SubmitJobRequest request;
  request.mutable_goal()->set_map_id("hall");
  *request.mutable_goal()->mutable_goal() = ToProto(Pose2(18, 4, 0));
  v1::SubmitJobResponse submitted;
  ASSERT_TRUE(fleet_->SubmitJob(&context, request, &submitted).ok());
  std::string assigned;
  for (int i = 0; i < 400 && assigned.empty(); ++i) {
    grpc::ClientContext get_context;
    v1::GetJobRequest get;
    get.set_job_id(submitted.job().job_id());
    v1::GetJobResponse job;
    if (fleet_->GetJob(&get_context, get, &job).ok()) assigned = job.job().assigned_robot_id();
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_EQ(assigned, "in-the-open");
  for (const auto& robot : robots) {
    robot->context.TryCancel();
    (void)robot->stream->Finish();
  }
}

// A robot whose battery falls below 20 % is sent to its charger (the map's charging route)
// before any other job, and gets other work again only once charged to 90 %.
TEST_F(JobFlowTest, ALowRobotIsSentToChargeFirstAndWorksAgainOnceCharged) {
  PutHall();
  Route charge;
  charge.name = "hall-charge";
  charge.map_id = "hall";
  charge.actions.push_back(RouteAction{StraightAction{1.0, 0.25}, {}});
  ASSERT_TRUE(PutRoute(charge).ok());
  Route work = charge;
  work.name = "hall-work";
  ASSERT_TRUE(PutRoute(work).ok());
  auto agents = v1::AgentService::NewStub(channel_);
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(20));
  std::unique_ptr<AgentStream> stream = agents->Connect(&context);
  v1::AgentMessage hello;
  *hello.mutable_hello() = ToProto(RobotIdentity{"r1", LelyVectorModel(), {"straight"}, "test"});
  ASSERT_TRUE(stream->Write(hello));
  int64_t sequence = 0;
  auto report_battery = [&](double fraction, const std::string& job_id) {
    Telemetry telemetry;
    telemetry.stamp_ns = ++sequence;
    telemetry.sequence = static_cast<uint64_t>(sequence);
    telemetry.pose_in_map = Pose2(5, 5, 0);
    telemetry.battery_fraction = fraction;
    telemetry.job_id = job_id;
    v1::AgentMessage wire;
    *wire.mutable_telemetry() = ToProto(telemetry);
    return stream->Write(wire);
  };
  ASSERT_TRUE(report_battery(0.12, ""));
  // The battery is known before there is work.
  EXPECT_TRUE(WaitUntilRobot("r1", [](const v1::RobotState& robot) {
    return robot.last_telemetry().battery_fraction() > 0.0;
  }));
  v1::SubmitJobResponse submitted;
  ASSERT_TRUE(Submit("hall-work", "", &submitted).ok());
  const std::string work_id = submitted.job().job_id();
  // The first assignment is the charging route, although the work job came first.
  v1::ServerMessage message;
  do {
    ASSERT_TRUE(stream->Read(&message));
  } while (!message.has_assignment());
  EXPECT_EQ(message.assignment().route().name(), "hall-charge");
  EXPECT_EQ(message.assignment().job().assigned_robot_id(), "r1");
  const std::string charge_id = message.assignment().job().job_id();
  ASSERT_TRUE(stream->Write(EventFor(charge_id, v1::AgentEvent::TYPE_ACTION_STARTED)));
  ASSERT_TRUE(stream->Write(EventFor(charge_id, v1::AgentEvent::TYPE_JOB_SUCCEEDED)));
  auto work_state = [&] {
    grpc::ClientContext get_context;
    v1::GetJobRequest get;
    get.set_job_id(work_id);
    v1::GetJobResponse job;
    EXPECT_TRUE(fleet_->GetJob(&get_context, get, &job).ok());
    return job.job().state();
  };
  // Docked and charging, but at 50 %: still no work (several dispatcher passes).
  ASSERT_TRUE(report_battery(0.5, ""));
  std::this_thread::sleep_for(std::chrono::milliseconds(600));
  EXPECT_EQ(work_state(), v1::JOB_STATE_QUEUED);
  // Charged: the work job goes to it.
  ASSERT_TRUE(report_battery(0.95, ""));
  do {
    ASSERT_TRUE(stream->Read(&message));
  } while (!message.has_assignment());
  EXPECT_EQ(message.assignment().job().job_id(), work_id);
  context.TryCancel();
  (void)stream->Finish();
}

// A robot whose job was re-queued after the lost-robot timeout and given to another robot is told
// to cancel it, with the reason, before it is handed a new job: otherwise it would drive the old
// job and the new one at once.
TEST_F(JobFlowTest, ARobotThatLostItsJobIsToldCancelBeforeItsNextJob) {
  PutBarn();
  ASSERT_TRUE(PutRoute(StraightRoute("long", 8.0)).ok());
  v1::SubmitJobResponse first;
  {
    grpc::ClientContext context;
    v1::SubmitJobRequest request;
    request.set_route_name("long");
    request.set_robot_id("");
    request.set_on_robot_lost(v1::REQUEUE_POLICY_REQUEUE);
    ASSERT_TRUE(fleet_->SubmitJob(&context, request, &first).ok());
  }
  const std::string old_job = first.job().job_id();
  auto agents = v1::AgentService::NewStub(channel_);
  auto job_of = [&](const std::string& job_id) {
    grpc::ClientContext context;
    v1::GetJobRequest get;
    get.set_job_id(job_id);
    v1::GetJobResponse job;
    EXPECT_TRUE(fleet_->GetJob(&context, get, &job).ok());
    return job.job();
  };
  {
    grpc::ClientContext context;
    std::unique_ptr<AgentStream> ra = agents->Connect(&context);
    ASSERT_TRUE(ra->Write(HelloFor("ra", "")));
    v1::ServerMessage message;
    ASSERT_TRUE(ra->Read(&message));  // welcome
    ASSERT_TRUE(ra->Read(&message));
    ASSERT_EQ(message.assignment().job().job_id(), old_job);
    ASSERT_TRUE(ra->Write(EventFor(old_job, v1::AgentEvent::TYPE_ACTION_STARTED)));
    ra->WritesDone();
    (void)ra->Finish();
  }
  // ra stays away past the lost-robot timeout (0.5 s): the job is re-queued and rb takes it.
  for (int i = 0; i < 300 && job_of(old_job).state() != v1::JOB_STATE_QUEUED; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_EQ(job_of(old_job).state(), v1::JOB_STATE_QUEUED);
  grpc::ClientContext rb_context;
  std::unique_ptr<AgentStream> rb = agents->Connect(&rb_context);
  ASSERT_TRUE(rb->Write(HelloFor("rb", "")));
  v1::ServerMessage message;
  ASSERT_TRUE(rb->Read(&message));  // welcome
  ASSERT_TRUE(rb->Read(&message));
  ASSERT_EQ(message.assignment().job().job_id(), old_job);

  v1::SubmitJobResponse second;
  ASSERT_TRUE(Submit("long", "", &second).ok());
  // ra comes back still driving the old job: first it hears that the job is no longer its own.
  grpc::ClientContext ra_context;
  std::unique_ptr<AgentStream> ra = agents->Connect(&ra_context);
  ASSERT_TRUE(ra->Write(HelloFor("ra", old_job)));
  ASSERT_TRUE(ra->Read(&message));
  ASSERT_TRUE(message.has_welcome());
  ASSERT_TRUE(ra->Read(&message));
  ASSERT_TRUE(message.has_command()) << message.DebugString();
  EXPECT_EQ(message.command().type(), v1::Command::TYPE_CANCEL);
  EXPECT_EQ(message.command().job_id(), old_job);
  EXPECT_THAT(message.command().reason(), ::testing::HasSubstr("rb"));
  ASSERT_TRUE(ra->Read(&message));
  ASSERT_TRUE(message.has_assignment());
  EXPECT_EQ(message.assignment().job().job_id(), second.job().job_id());
  EXPECT_EQ(job_of(old_job).assigned_robot_id(), "rb");  // the old job stays rb's
  ra->WritesDone();
  (void)ra->Finish();
  rb->WritesDone();
  (void)rb->Finish();
}

// An operator pauses a running job: the robot is told to stop (PAUSE) and the job shows paused;
// resuming tells it to go on (RESUME). Jobs in other states are refused with the state named.
TEST_F(JobFlowTest, AnOperatorPausesAndResumesARunningJob) {
  PutBarn();
  ASSERT_TRUE(PutRoute(StraightRoute("long", 8.0)).ok());
  v1::SubmitJobResponse submitted;
  ASSERT_TRUE(Submit("long", "", &submitted).ok());
  const std::string job_id = submitted.job().job_id();
  auto pause = [&](const std::string& id) {
    grpc::ClientContext context;
    v1::PauseJobRequest request;
    request.set_job_id(id);
    request.set_reason("cows in the feed alley");
    v1::PauseJobResponse response;
    const grpc::Status status = fleet_->PauseJob(&context, request, &response);
    return std::make_pair(status, response.job());
  };
  auto resume = [&](const std::string& id) {
    grpc::ClientContext context;
    v1::ResumeJobRequest request;
    request.set_job_id(id);
    v1::ResumeJobResponse response;
    const grpc::Status status = fleet_->ResumeJob(&context, request, &response);
    return std::make_pair(status, response.job());
  };
  EXPECT_EQ(pause("job-999999").first.error_code(), grpc::StatusCode::NOT_FOUND);

  auto agents = v1::AgentService::NewStub(channel_);
  grpc::ClientContext agent_context;
  std::unique_ptr<AgentStream> agent = agents->Connect(&agent_context);
  ASSERT_TRUE(agent->Write(HelloFor("lely1", "")));
  v1::ServerMessage message;
  ASSERT_TRUE(agent->Read(&message));  // welcome
  ASSERT_TRUE(agent->Read(&message));
  ASSERT_EQ(message.assignment().job().job_id(), job_id);
  EXPECT_EQ(resume(job_id).first.error_code(), grpc::StatusCode::FAILED_PRECONDITION);

  const auto [paused, paused_job] = pause(job_id);
  ASSERT_TRUE(paused.ok()) << paused.error_message();
  EXPECT_EQ(paused_job.state(), v1::JOB_STATE_PAUSED);
  // Clearances may come first; the command follows.
  do {
    ASSERT_TRUE(agent->Read(&message));
  } while (!message.has_command());
  EXPECT_EQ(message.command().type(), v1::Command::TYPE_PAUSE);
  EXPECT_EQ(message.command().job_id(), job_id);
  EXPECT_EQ(message.command().reason(), "cows in the feed alley");
  const grpc::Status twice = pause(job_id).first;
  EXPECT_EQ(twice.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_THAT(twice.error_message(), ::testing::HasSubstr("paused"));

  const auto [resumed, resumed_job] = resume(job_id);
  ASSERT_TRUE(resumed.ok()) << resumed.error_message();
  EXPECT_EQ(resumed_job.state(), v1::JOB_STATE_RUNNING);
  do {
    ASSERT_TRUE(agent->Read(&message));
  } while (!message.has_command());
  EXPECT_EQ(message.command().type(), v1::Command::TYPE_RESUME);

  ASSERT_TRUE(agent->Write(EventFor(job_id, v1::AgentEvent::TYPE_JOB_SUCCEEDED)));
  const std::vector<v1::JobEvent> events = WatchToTheEnd(job_id);
  std::vector<v1::JobEventType> types;
  for (const auto& e : events) types.push_back(e.type());
  EXPECT_THAT(types, ::testing::IsSupersetOf({v1::JOB_EVENT_TYPE_PAUSED, v1::JOB_EVENT_TYPE_RESUMED,
                                              v1::JOB_EVENT_TYPE_SUCCEEDED}));
  agent->WritesDone();
  (void)agent->Finish();
}

}  // namespace
}  // namespace fleetnav
