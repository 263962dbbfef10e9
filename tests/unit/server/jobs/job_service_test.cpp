// JobService as the use-case layer, without gRPC: in-memory repositories, a mailbox that records
// what robots are told, and a ManualClock, so that lost-robot timeouts are checked in injected
// time rather than by waiting.
#include "fleetnav/server/jobs/job_service.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/clock.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/server/jobs/dispatcher_loop.hpp"
#include "fleetnav/server/robots/fleet_registry.hpp"
#include "fleetnav/server/site/map_catalog.hpp"
#include "fleetnav/server/site/site_cache.hpp"
#include "fleetnav/server/site/site_catalog.hpp"
#include "fleetnav/storage/memory/memory_fleet_repositories.hpp"
#include "fleetnav/storage/memory/memory_map_repository.hpp"
#include "memory_site.hpp"

namespace fleetnav::server {
namespace {

using ::testing::HasSubstr;

constexpr int64_t kSecondNs = 1'000'000'000;

/// What the service told each robot, in order.
class RecordingMailbox : public RobotMailbox {
 public:
  bool SendAssignment(const std::string& robot_id, const JobAssignment& assignment) override {
    assignments[robot_id].push_back(assignment);
    return true;
  }
  bool SendCommand(const std::string& robot_id, const JobCommand& command) override {
    commands[robot_id].push_back(command);
    return true;
  }
  bool SendClearance(const std::string&, const ClearanceNotice&) override { return true; }
  void BroadcastMapUpdate(const std::string&, uint32_t, uint32_t) override {}

  std::map<std::string, std::vector<JobAssignment>> assignments;
  std::map<std::string, std::vector<JobCommand>> commands;
};

class JobServiceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(memory_.hall_ok);
    Route alley;
    alley.name = "alley";
    alley.map_id = "hall";
    alley.actions.push_back(RouteAction{StraightAction{3.0, 0.25}, {}});
    ASSERT_TRUE(site_.PutRoute(alley).ok());
    JobServiceParams params;
    params.lost_robot_timeout_s = 30.0;
    jobs_ = std::make_unique<JobService>(&job_store_, &memory_.robots, &site_data_, &site_,
                                         &registry_, &mailbox_, &clock_, params);
    ASSERT_TRUE(jobs_->Recover().ok());
  }

  /// A robot connecting as the agent service connects it.
  uint64_t Connect(const std::string& robot_id) {
    RobotIdentity identity;
    identity.robot_id = robot_id;
    identity.model = LelyVectorModel();
    identity.capabilities = {"straight", "turn"};
    jobs_->OnRobotConnected(identity, "");
    return registry_.Connect(identity);
  }

  std::string Submit(RequeuePolicy on_lost) {
    SubmitJobRequest request;
    request.route_name = "alley";
    request.on_robot_lost = on_lost;
    absl::StatusOr<storage::CreatedJob> created = jobs_->Submit(request);
    EXPECT_TRUE(created.ok()) << created.status();
    return created.ok() ? created->job.job_id : "";
  }

  /// A job service with traffic coordination over this fixture's site and fleet, recovered.
  struct CoordinatedJobs {
    explicit CoordinatedJobs(JobServiceTest& t)
        : traffic(&t.site_data_, &t.registry_, &t.mailbox_, &t.clock_, TrafficCoordinatorParams{}),
          jobs(&t.job_store_, &t.memory_.robots, &t.site_data_, &t.site_, &t.registry_, &t.mailbox_,
               &t.clock_, JobServiceParams{}, &traffic) {}
    TrafficCoordinator traffic;
    JobService jobs;
  };
  std::unique_ptr<CoordinatedJobs> WithTraffic() {
    auto coordinated = std::make_unique<CoordinatedJobs>(*this);
    EXPECT_TRUE(coordinated->jobs.Recover().ok());
    return coordinated;
  }

  /// A robot that drives goal jobs, connected to `jobs` and standing at `pose` (telemetry in
  /// map); returns its session.
  uint64_t ConnectGoalRobot(JobService& jobs, const std::string& robot_id, const Pose2& pose) {
    RobotIdentity identity;
    identity.robot_id = robot_id;
    identity.model = LelyVectorModel();
    identity.capabilities = {"free_navigation"};
    jobs.OnRobotConnected(identity, "");
    const uint64_t session = registry_.Connect(identity);
    Telemetry telemetry;
    telemetry.pose_in_map = pose;
    EXPECT_TRUE(registry_.RecordTelemetry(robot_id, session, telemetry).ok());
    return session;
  }

  /// Two passes send the idle `robot_id`, which stands in a waiting robot's way, to make way
  /// (its first assignment); its bumper then fails that job.
  void FailToMakeWay(JobService& jobs, const std::string& robot_id) {
    jobs.DispatchOnce();
    jobs.DispatchOnce();
    ASSERT_EQ(mailbox_.assignments[robot_id].size(), 1u);  // its make-way job
    JobEvent failed;
    failed.job_id = mailbox_.assignments[robot_id].back().job.job_id;
    failed.type = JobEventType::kFailed;
    failed.reason = "bumper pressed";
    jobs.OnRobotEvent(robot_id, failed);
  }

  std::string SubmitGoal(JobService& jobs, const std::string& robot_id, const std::string& map_id,
                         const Pose2& goal) {
    SubmitJobRequest request;
    request.goal_map_id = map_id;
    request.goal = goal;
    request.robot_id = robot_id;
    absl::StatusOr<storage::CreatedJob> created = jobs.Submit(request);
    EXPECT_TRUE(created.ok()) << created.status();
    return created.ok() ? created->job.job_id : "";
  }

  JobState StateOf(const std::string& job_id) { return jobs_->Get(job_id).value().state; }

  /// Submits, assigns to `robot`, has it start, then cuts it off.
  std::string RunningJobWhoseRobotDrops(const std::string& robot, RequeuePolicy on_lost) {
    const uint64_t session = Connect(robot);
    const std::string job_id = Submit(on_lost);
    EXPECT_EQ(jobs_->DispatchOnce(), 1);
    EXPECT_EQ(mailbox_.assignments[robot].size(), 1u);
    JobEvent started;
    started.job_id = job_id;
    started.type = JobEventType::kActionStarted;
    started.action_index = 0;
    jobs_->OnRobotEvent(robot, started);
    EXPECT_EQ(StateOf(job_id), JobState::kRunning);
    EXPECT_TRUE(registry_.Disconnect(robot, session));
    jobs_->OnRobotDisconnected(robot);
    EXPECT_EQ(StateOf(job_id), JobState::kPaused);
    return job_id;
  }

  ManualClock clock_{1000 * kSecondNs};
  testing::MemorySite memory_{&clock_};
  storage::MemoryJobRepository& job_store_ = memory_.jobs;
  SiteCache& site_data_ = memory_.cache;
  SiteCatalog& site_ = memory_.catalog;
  FleetRegistry registry_{&clock_, FleetRegistryParams{}};
  RecordingMailbox mailbox_;
  std::unique_ptr<JobService> jobs_;
};

TEST_F(JobServiceTest, AQueuedJobGoesToTheIdleCapableRobot) {
  const std::string job_id = Submit(RequeuePolicy::kFail);
  EXPECT_EQ(jobs_->DispatchOnce(), 0);  // nobody connected
  EXPECT_EQ(StateOf(job_id), JobState::kQueued);
  Connect("lely1");
  EXPECT_EQ(jobs_->DispatchOnce(), 1);
  EXPECT_EQ(StateOf(job_id), JobState::kAssigned);
  ASSERT_EQ(mailbox_.assignments["lely1"].size(), 1u);
  const JobAssignment& sent = mailbox_.assignments["lely1"][0];
  EXPECT_EQ(sent.job.job_id, job_id);
  EXPECT_EQ(sent.route->name, "alley");
  EXPECT_EQ(sent.map_version, 1u);
}

TEST_F(JobServiceTest, AJobPinnedToAConnectedRobotThatCannotRunItIsRefusedAndNotStored) {
  Route spin;
  spin.name = "spin";
  spin.map_id = "hall";
  spin.actions.push_back(RouteAction{StraightAction{1.0, 0.25}, {}});
  spin.actions.push_back(RouteAction{TurnAction{1.57, 0.3}, {}});
  ASSERT_TRUE(site_.PutRoute(spin).ok());
  RobotIdentity car;
  car.robot_id = "car1";
  car.model = AckermannDeliveryModel();
  car.capabilities = {"straight", "free_navigation"};  // an Ackermann robot cannot turn on the spot
  jobs_->OnRobotConnected(car, "");
  const uint64_t session = registry_.Connect(car);
  SubmitJobRequest request;
  request.route_name = "spin";
  request.robot_id = "car1";
  const absl::Status refused = jobs_->Submit(request).status();
  EXPECT_EQ(refused.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_THAT(refused.message(),
              HasSubstr("robot car1 (ackermann-delivery) cannot run actions[1] (turn)"));
  EXPECT_TRUE(jobs_->List(storage::JobFilter{}).value().jobs.empty());
  // The same robot can run the straight route; and once it is away it may come back able to.
  request.route_name = "alley";
  EXPECT_TRUE(jobs_->Submit(request).ok());
  EXPECT_TRUE(registry_.Disconnect("car1", session));
  jobs_->OnRobotDisconnected("car1");
  request.route_name = "spin";
  EXPECT_TRUE(jobs_->Submit(request).ok());
}

// A goal no robot can stand at or drive to is refused at submission, naming the robot and why,
// instead of sending a robot that searches and fails; nothing is stored.
TEST_F(JobServiceTest, AGoalARobotCannotStandAtOrReachIsRefusedAndNotStored) {
  // Two rooms, 5 m each, with a wall between them and no door.
  OccupancyGrid rooms = OccupancyGrid::Filled(100, 100, 0.1, Pose2(), 0).value();
  for (int y = 0; y < 100; ++y) rooms.SetValue({50, y}, OccupancyGrid::kOccupiedValue);
  ASSERT_TRUE(MapCatalog(&site_data_, &clock_).Put("rooms", rooms, "").ok());
  ConnectGoalRobot(*jobs_, "a", Pose2(2.5, 5.0, 0.0));
  const auto submit = [&](const std::string& robot_id, double x_m, double y_m) {
    SubmitJobRequest request;
    request.goal_map_id = "rooms";
    request.goal = Pose2(x_m, y_m, 0.0);
    request.robot_id = robot_id;
    return jobs_->Submit(request).status();
  };
  const absl::Status closed_room = submit("a", 8.0, 5.0);
  EXPECT_EQ(closed_room.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_EQ(closed_room.message(),
            "goal.goal: robot a (lely-vector) cannot reach (8.00, 5.00) from where it stands "
            "(2.50, 5.00): no way on map 'rooms' between the two is as wide as its footprint's "
            "inscribed circle (1.60 m across)");
  // A free cell beside the wall, nearer it than the robot is wide.
  const absl::Status too_near = submit("a", 4.85, 5.0);
  EXPECT_EQ(too_near.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_THAT(too_near.message(), HasSubstr("robot a (lely-vector) does not fit at (4.85, 5.00)"));
  // Unpinned, the only robot that navigates freely cannot go there either.
  EXPECT_EQ(submit("", 8.0, 5.0).code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_TRUE(jobs_->List(storage::JobFilter{}).value().jobs.empty());
  // In its own room it can; and once a robot stands in the other room, an unpinned job there is
  // taken while the one pinned to a is still refused.
  EXPECT_TRUE(submit("a", 2.5, 2.5).ok());
  ConnectGoalRobot(*jobs_, "b", Pose2(7.5, 5.0, kPi));
  EXPECT_TRUE(submit("", 8.0, 5.0).ok());
  EXPECT_EQ(submit("a", 8.0, 5.0).code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_EQ(jobs_->List(storage::JobFilter{}).value().jobs.size(), 2u);
}

TEST_F(JobServiceTest, AJobNoRobotHasEverBeenAbleToRunSaysSoFromTheFirstPass) {
  Route fence;
  fence.name = "fence";
  fence.map_id = "hall";
  fence.actions.push_back(RouteAction{StraightAction{1.0, 0.25}, {}});
  fence.actions.push_back(RouteAction{FenceNavigationAction{Side::kLeft, 0.5, 3.0, 0.25}, {}});
  ASSERT_TRUE(site_.PutRoute(fence).ok());
  const uint64_t session = Connect("lely1");  // straight and turn only
  SubmitJobRequest request;
  request.route_name = "fence";
  const absl::StatusOr<storage::CreatedJob> created = jobs_->Submit(request);
  ASSERT_TRUE(created.ok()) << created.status();
  EXPECT_EQ(jobs_->DispatchOnce(), 0);
  EXPECT_EQ(jobs_->Get(created->job.job_id).value().reason,
            "no robot that has connected can run actions[1] (fence_navigation)");
  // A job the fleet could run, were its robot connected, says that instead.
  const std::string alley = Submit(RequeuePolicy::kFail);
  EXPECT_TRUE(registry_.Disconnect("lely1", session));
  jobs_->OnRobotDisconnected("lely1");
  EXPECT_EQ(jobs_->DispatchOnce(), 0);
  EXPECT_EQ(jobs_->Get(alley).value().reason, "no connected robot can run actions[0] (straight)");
}

TEST_F(JobServiceTest, JobAndEventTimesAreTheInjectedClocksCalendar) {
  const std::string job_id = Submit(RequeuePolicy::kFail);
  clock_.AdvanceNs(7 * kSecondNs);
  Connect("lely1");
  ASSERT_EQ(jobs_->DispatchOnce(), 1);
  const Job job = jobs_->Get(job_id).value();
  // The clock starts at 1000 s with its calendar origin at 1970: no wall time gets in.
  EXPECT_EQ(job.created_unix_ms, 1'000'000);
  EXPECT_EQ(job.updated_unix_ms, 1'007'000);
  const std::vector<JobEvent> events = jobs_->Events(job_id, 0).value();
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].type, JobEventType::kQueued);
  EXPECT_EQ(events[0].unix_ms, 1'000'000);
  EXPECT_EQ(events[1].type, JobEventType::kAssigned);
  EXPECT_EQ(events[1].unix_ms, 1'007'000);
}

TEST_F(JobServiceTest, ALostRobotsJobFailsAfterTheTimeoutOfTheInjectedClock) {
  const std::string job_id = RunningJobWhoseRobotDrops("lely1", RequeuePolicy::kFail);
  clock_.AdvanceNs(29 * kSecondNs);
  jobs_->DispatchOnce();
  EXPECT_EQ(StateOf(job_id), JobState::kPaused);  // 29 s: still waiting for the robot
  clock_.AdvanceNs(2 * kSecondNs);
  jobs_->DispatchOnce();
  const Job job = jobs_->Get(job_id).value();
  EXPECT_EQ(job.state, JobState::kFailed);
  EXPECT_THAT(job.reason, HasSubstr("robot lely1 lost for 30 s"));
}

TEST_F(JobServiceTest, ALostRobotsJobIsQueuedAgainWhenItsPolicySaysSo) {
  const std::string job_id = RunningJobWhoseRobotDrops("lely1", RequeuePolicy::kRequeue);
  clock_.AdvanceNs(31 * kSecondNs);
  jobs_->DispatchOnce();
  EXPECT_EQ(StateOf(job_id), JobState::kQueued);
  // Another robot takes it.
  Connect("lely2");
  EXPECT_EQ(jobs_->DispatchOnce(), 1);
  EXPECT_EQ(jobs_->Get(job_id).value().assigned_robot_id, "lely2");
}

TEST_F(JobServiceTest, ARobotBackBeforeTheTimeoutResumesItsJob) {
  const std::string job_id = RunningJobWhoseRobotDrops("lely1", RequeuePolicy::kFail);
  clock_.AdvanceNs(20 * kSecondNs);
  RobotIdentity identity;
  identity.robot_id = "lely1";
  identity.model = LelyVectorModel();
  identity.capabilities = {"straight", "turn"};
  jobs_->OnRobotConnected(identity, job_id);
  registry_.Connect(identity);
  EXPECT_EQ(StateOf(job_id), JobState::kRunning);
  clock_.AdvanceNs(60 * kSecondNs);
  jobs_->DispatchOnce();
  EXPECT_EQ(StateOf(job_id), JobState::kRunning);  // the timeout no longer runs
}

// Two robots sent to each other's places: the newer job is withdrawn (queued again), its robot
// goes aside on a make-way job first, and gets its job back once that has ended.
TEST_F(JobServiceTest, OfTwoRobotsSwappingPlacesTheNewerJobWaitsWhileItsRobotMakesWay) {
  const std::unique_ptr<CoordinatedJobs> coordinated = WithTraffic();
  JobService& jobs = coordinated->jobs;
  ConnectGoalRobot(jobs, "a", Pose2(2.5, 5.0, 0.0));
  const uint64_t session_b = ConnectGoalRobot(jobs, "b", Pose2(7.5, 5.0, kPi));
  const std::string job_a = SubmitGoal(jobs, "a", "hall", Pose2(7.5, 5.0, 0.0));
  clock_.AdvanceNs(kSecondNs);
  const std::string job_b = SubmitGoal(jobs, "b", "hall", Pose2(2.5, 5.0, kPi));
  EXPECT_EQ(jobs.DispatchOnce(), 2);

  // b's job is back in the queue, saying why; b was told to drop it.
  const Job withdrawn = jobs.Get(job_b).value();
  EXPECT_EQ(withdrawn.state, JobState::kQueued);
  EXPECT_EQ(withdrawn.assigned_robot_id, "");
  ASSERT_FALSE(mailbox_.commands["b"].empty());
  EXPECT_EQ(mailbox_.commands["b"].back().type, JobCommandType::kCancel);
  EXPECT_EQ(mailbox_.commands["b"].back().job_id, job_b);
  EXPECT_THAT(mailbox_.commands["b"].back().reason,
              HasSubstr("withdrawn from b to let a pass (a circle of waits)"));
  EXPECT_EQ(jobs.Get(job_a).value().state, JobState::kAssigned);

  // The next pass gives b its make-way job: a goal off a's way, not its own job.
  jobs.DispatchOnce();
  ASSERT_EQ(mailbox_.assignments["b"].size(), 2u);
  const JobAssignment& make_way = mailbox_.assignments["b"].back();
  EXPECT_NE(make_way.job.job_id, job_b);
  ASSERT_TRUE(make_way.job.goal.has_value());
  EXPECT_GT(std::abs(make_way.job.goal->y_m() - 5.0), 1.0) << make_way.job.goal->y_m();
  EXPECT_EQ(StateOf(job_b), JobState::kQueued);

  // b has made way: its own job is given again.
  JobEvent done;
  done.job_id = make_way.job.job_id;
  done.type = JobEventType::kSucceeded;
  jobs.OnRobotEvent("b", done);
  Telemetry aside;
  aside.pose_in_map = *make_way.job.goal;
  ASSERT_TRUE(registry_.RecordTelemetry("b", session_b, aside).ok());
  jobs.DispatchOnce();
  EXPECT_EQ(StateOf(job_b), JobState::kAssigned);
  EXPECT_EQ(mailbox_.assignments["b"].back().job.job_id, job_b);
}

// A robot whose make-way job failed (its bumper closed) is not sent to make way again and again:
// before, two robots in contact were given a new make-way job on every dispatcher pass.
TEST_F(JobServiceTest, ARobotThatFailedToMakeWayIsNotSentAgainUntilAJobOfItsSucceeds) {
  const std::unique_ptr<CoordinatedJobs> coordinated = WithTraffic();
  JobService& jobs = coordinated->jobs;
  ConnectGoalRobot(jobs, "a", Pose2(1.5, 5.0, 0.0));
  ConnectGoalRobot(jobs, "c", Pose2(6.0, 5.0, kPi / 2));  // idle, on a's way
  SubmitGoal(jobs, "a", "hall", Pose2(8.5, 5.0, 0.0));
  FailToMakeWay(jobs, "c");
  for (int pass = 0; pass < 5; ++pass) {
    clock_.AdvanceNs(kSecondNs);
    jobs.DispatchOnce();
  }
  EXPECT_EQ(mailbox_.assignments["c"].size(), 1u);
}

// A job is withdrawn only for a robot that then goes aside: one that may not be sent to make way
// (its make-way job failed) keeps its held job. Before, the job was withdrawn, given again at
// once, held and withdrawn again on every pass.
TEST_F(JobServiceTest, AHeldJobIsNotWithdrawnFromARobotThatWillNotBeSentAside) {
  const std::unique_ptr<CoordinatedJobs> coordinated = WithTraffic();
  JobService& jobs = coordinated->jobs;
  ConnectGoalRobot(jobs, "a", Pose2(2.5, 5.0, 0.0));
  ConnectGoalRobot(jobs, "b", Pose2(7.5, 5.0, kPi));  // idle, where a ends
  SubmitGoal(jobs, "a", "hall", Pose2(7.5, 5.0, 0.0));
  FailToMakeWay(jobs, "b");
  // b is then sent to where a stands: the two swap places, and b's job is the one held.
  clock_.AdvanceNs(kSecondNs);
  const std::string job_b = SubmitGoal(jobs, "b", "hall", Pose2(2.5, 5.0, kPi));
  for (int pass = 0; pass < 5; ++pass) {
    clock_.AdvanceNs(kSecondNs);
    jobs.DispatchOnce();
  }
  EXPECT_EQ(StateOf(job_b), JobState::kAssigned);
  EXPECT_EQ(mailbox_.assignments["b"].size(), 2u);  // given once, never withdrawn
}

// Idle robots are obstacles by coordinates on every map (fleetnavd does not know where a robot
// without a job is); one whose last job was on another map stands on another site and is not
// sent to a place on this one.
TEST_F(JobServiceTest, ARobotLastOnAnotherMapIsNotSentToMakeWayHere) {
  ASSERT_TRUE(MapCatalog(&site_data_, &clock_)
                  .Put("other", OccupancyGrid::Filled(100, 100, 0.1, Pose2(), 0).value(), "")
                  .ok());
  const std::unique_ptr<CoordinatedJobs> coordinated = WithTraffic();
  JobService& jobs = coordinated->jobs;
  ConnectGoalRobot(jobs, "a", Pose2(1.5, 5.0, 0.0));
  ConnectGoalRobot(jobs, "c", Pose2(6.0, 5.0, kPi / 2));
  // c's last job was on "other"; it ended where c now stands.
  const std::string job_c = SubmitGoal(jobs, "c", "other", Pose2(6.0, 5.0, kPi / 2));
  EXPECT_EQ(jobs.DispatchOnce(), 1);
  JobEvent done;
  done.job_id = job_c;
  done.type = JobEventType::kSucceeded;
  jobs.OnRobotEvent("c", done);
  // a drives through where c stands, by coordinates, on "hall".
  SubmitGoal(jobs, "a", "hall", Pose2(8.5, 5.0, 0.0));
  jobs.DispatchOnce();
  jobs.DispatchOnce();
  EXPECT_EQ(mailbox_.assignments["c"].size(), 1u);  // only its job on "other"
}

TEST_F(JobServiceTest, TheDispatcherLoopAssignsOnItsThreadAndTimesTheOneJobPass) {
  DispatcherLoop loop(jobs_.get(), /*period_s=*/60.0);
  loop.Start();
  Connect("lely1");
  const std::string job_id = Submit(RequeuePolicy::kFail);  // wakes the dispatcher at once
  // The period is a minute: only the wake-up can have assigned it within the 10 s waited here.
  for (int i = 0; i < 1000 && StateOf(job_id) == JobState::kQueued; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  loop.Stop();
  EXPECT_EQ(StateOf(job_id), JobState::kAssigned);
  EXPECT_EQ(loop.assigning_passes().count, 1);
  EXPECT_EQ(loop.one_job_passes().count, 1);
  EXPECT_GE(loop.one_job_passes().max_ms, loop.one_job_passes().p50_ms);
  // The pass's CPU time is counted for the same pass, and a thread cannot use more CPU than
  // the wall time it ran (1 ms of slack for the two clocks' reads).
  EXPECT_EQ(loop.one_job_pass_cpu().count, 1);
  EXPECT_GT(loop.one_job_pass_cpu().max_ms, 0.0);
  EXPECT_LE(loop.one_job_pass_cpu().max_ms, loop.one_job_passes().max_ms + 1.0);
}

TEST(PassTimingsTest, KeepsTheLatestSamplesAndCountsThemAll) {
  PassTimings timings(/*capacity=*/100);
  for (int i = 1; i <= 100; ++i) timings.Add(i);
  PassFigures f = timings.Figures();
  EXPECT_EQ(f.count, 100);
  EXPECT_DOUBLE_EQ(f.p50_ms, 51.0);
  EXPECT_DOUBLE_EQ(f.p99_ms, 100.0);
  EXPECT_DOUBLE_EQ(f.max_ms, 100.0);
  // 100 more of 1 ms overwrite the old ones: the figures are of the latest hundred.
  for (int i = 0; i < 100; ++i) timings.Add(1.0);
  f = timings.Figures();
  EXPECT_EQ(f.count, 200);
  EXPECT_DOUBLE_EQ(f.max_ms, 1.0);
}

}  // namespace
}  // namespace fleetnav::server
