// The job runner on its own seam: steps and serves driven by hand, a fake job channel, an
// odometry localizer that is never updated (the robot is taken to stand where it started).
#include "fleetnav/robot_agent/job_runner.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/localization/dead_reckoning_localizer.hpp"

namespace fleetnav::agent {
namespace {

/// Hands out one assignment and then whatever commands the test queues.
class ScriptedChannel : public JobChannel {
 public:
  std::optional<JobAssignment> TakeAssignment() override { return std::exchange(assignment, {}); }
  std::vector<JobCommand> TakeCommands() override { return std::exchange(commands, {}); }
  void ReportEvent(const JobEvent& event) override { reported.push_back(event); }
  void SetCurrentJob(const std::string& job_id) override { current.push_back(job_id); }
  bool HearsServer() override { return hears_server; }
  std::vector<RobotStop> Stops() override { return stops; }

  bool hears_server = true;
  std::vector<RobotStop> stops;
  std::optional<JobAssignment> assignment;
  std::vector<JobCommand> commands;
  std::vector<JobEvent> reported;
  std::vector<std::string> current;  ///< every SetCurrentJob, in order
};

class JobRunnerTest : public ::testing::Test {
 protected:
  JobAssignment StraightJob(const std::string& job_id) {
    JobAssignment assignment;
    assignment.job.job_id = job_id;
    Route route;
    route.name = "ahead";
    route.actions = {{StraightAction{2.0, 0.25}, {}}};
    assignment.route = std::make_shared<const Route>(route);
    return assignment;
  }

  std::unique_ptr<JobRunner> Runner(std::optional<Eigen::Vector2d> carried = std::nullopt) {
    RouteContext context;
    context.model = MecanumPlatformModel();
    context.carried_load_m = carried;
    return std::make_unique<JobRunner>(context, JobRunnerPorts{&channel_, nullptr, {}, &odometry_},
                                       ModeParams{}, SafetyParams{}, std::nullopt);
  }

  ExecutorOutput Tick(JobRunner& runner) {
    ControlInput input;
    input.dt_s = 0.02;
    const ExecutorOutput output = runner.Step(input, {}, odometry_.estimate(), Twist2{});
    runner.Serve(output);
    return output;
  }

  ScriptedChannel channel_;
  localization::DeadReckoningLocalizer odometry_ =
      localization::DeadReckoningLocalizer::Create(MecanumPlatformModel(), Pose2()).value();
};

TEST_F(JobRunnerTest, AJobWaitsForItsClearanceAndAPauseHoldsItStill) {
  auto runner = Runner();
  channel_.assignment = StraightJob("job-1");
  Tick(*runner);
  EXPECT_EQ(runner->job_id(), "job-1");
  EXPECT_THAT(channel_.current, ::testing::ElementsAre("job-1"));
  // Not cleared: standing, waiting.
  ExecutorOutput out = Tick(*runner);
  EXPECT_EQ(out.command.vx_mps, 0.0);
  channel_.commands = {JobCommand{JobCommandType::kClearance, "job-1", "", 0}};
  Tick(*runner);
  out = Tick(*runner);
  EXPECT_GT(out.command.vx_mps, 0.0);
  // A pause of another job is ignored; this job's holds the robot still.
  channel_.commands = {JobCommand{JobCommandType::kPause, "job-9", "why"}};
  Tick(*runner);
  EXPECT_GT(Tick(*runner).command.vx_mps, 0.0);
  channel_.commands = {JobCommand{JobCommandType::kPause, "job-1", "why"}};
  Tick(*runner);
  out = Tick(*runner);
  EXPECT_EQ(out.mode, NavigationMode::kPaused);
  EXPECT_EQ(out.command.vx_mps, 0.0);
  channel_.commands = {JobCommand{JobCommandType::kResume, "job-1", ""}};
  Tick(*runner);
  EXPECT_GT(Tick(*runner).command.vx_mps, 0.0);
}

TEST_F(JobRunnerTest, ARobotThatDoesNotHearTheServerForASecondStandsUntilItHearsItAgain) {
  auto runner = Runner();  // SafetyParams' default: 1 s
  channel_.assignment = StraightJob("job-1");
  channel_.commands = {JobCommand{JobCommandType::kClearance, "job-1", "", 0}};
  Tick(*runner);
  ASSERT_GT(Tick(*runner).command.vx_mps, 0.0);
  channel_.hears_server = false;
  // Within the second (49 ticks of 20 ms) it drives on within its clearance ...
  for (int i = 0; i < 49; ++i) ASSERT_GT(Tick(*runner).command.vx_mps, 0.0) << i;
  // ... then stands, its job held (not failed), for as long as the server is not heard.
  for (int i = 0; i < 200; ++i) {
    const ExecutorOutput out = Tick(*runner);
    ASSERT_EQ(out.command.vx_mps, 0.0) << i;
    ASSERT_EQ(out.mode, NavigationMode::kPaused);
  }
  EXPECT_EQ(runner->job_id(), "job-1");
  EXPECT_EQ(runner->state(), ExecutionState::kRunning);
  channel_.hears_server = true;
  EXPECT_GT(Tick(*runner).command.vx_mps, 0.0);
}

TEST_F(JobRunnerTest, ACancelEndsTheJobReportsItAndTheNextJobMayCome) {
  auto runner = Runner();
  channel_.assignment = StraightJob("job-1");
  channel_.commands = {JobCommand{JobCommandType::kClearance, "job-1", "", 0}};
  Tick(*runner);
  Tick(*runner);
  channel_.commands = {JobCommand{JobCommandType::kCancel, "job-1", "operator"}};
  Tick(*runner);
  EXPECT_TRUE(runner->job_id().empty());
  EXPECT_EQ(runner->jobs_finished(), 1);
  ASSERT_FALSE(channel_.reported.empty());
  EXPECT_EQ(channel_.reported.back().type, JobEventType::kCancelled);
  EXPECT_EQ(channel_.reported.back().reason, "operator");
  EXPECT_EQ(channel_.current.back(), "");
  channel_.assignment = StraightJob("job-2");
  Tick(*runner);
  EXPECT_EQ(runner->job_id(), "job-2");
}

TEST_F(JobRunnerTest, TheCarriedLoadOutlivesTheRouteThatCarriedIt) {
  const Eigen::Vector2d trolley(1.1, 0.8);
  auto runner = Runner(trolley);
  channel_.assignment = StraightJob("job-1");
  Tick(*runner);
  ASSERT_EQ(runner->carried_load_m(), std::optional<Eigen::Vector2d>(trolley));
  // Cancelled while carrying: the load is still on the lift, for the next route to start from.
  channel_.commands = {JobCommand{JobCommandType::kCancel, "job-1", ""}};
  Tick(*runner);
  EXPECT_TRUE(runner->job_id().empty());
  EXPECT_EQ(runner->carried_load_m(), std::optional<Eigen::Vector2d>(trolley));
}

TEST_F(JobRunnerTest, AStoppedZoneAheadStopsTheRobotShortOfItOneBehindDoesNotOneUnderItHoldsIt) {
  auto runner = Runner();
  JobAssignment job = StraightJob("job-1");  // 2 m east from the origin
  job.job.map_id = "hall";
  channel_.assignment = job;
  channel_.commands = {JobCommand{JobCommandType::kClearance, "job-1", "", 0}};
  Tick(*runner);
  ASSERT_GT(Tick(*runner).command.vx_mps, 0.0);
  const double reach_m = MecanumPlatformModel().CircumscribedRadius();
  const auto zone_from = [&](double x0_m, double x1_m, const std::string& map_id) {
    RobotStop stop;
    stop.map_id = map_id;
    stop.zone = "pen";
    stop.polygon_in_map = {{x0_m, -2.0}, {x1_m, -2.0}, {x1_m, 2.0}, {x0_m, 2.0}};
    return stop;
  };
  // Ahead, its reach (and 5 cm to spare) at the zone's edge: it stands, its job not held.
  channel_.stops = {zone_from(reach_m + 0.05, 5.0, "hall")};
  ExecutorOutput out = Tick(*runner);
  EXPECT_EQ(out.command.vx_mps, 0.0);
  EXPECT_NE(out.mode, NavigationMode::kPaused);
  // Another map's stop, or a zone behind it: it drives on.
  channel_.stops = {zone_from(reach_m + 0.05, 5.0, "store"),
                    zone_from(-5.0, -reach_m - 0.3, "hall")};
  EXPECT_GT(Tick(*runner).command.vx_mps, 0.0);
  // Its body in the zone: held.
  channel_.stops = {zone_from(-1.0, 1.0, "hall")};
  out = Tick(*runner);
  EXPECT_EQ(out.command.vx_mps, 0.0);
  EXPECT_EQ(out.mode, NavigationMode::kPaused);
  channel_.stops = {};
  EXPECT_GT(Tick(*runner).command.vx_mps, 0.0);
  EXPECT_EQ(runner->state(), ExecutionState::kRunning);
}

}  // namespace
}  // namespace fleetnav::agent
