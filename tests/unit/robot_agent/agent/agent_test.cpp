// The agent's control loop over a fake HAL: a kinematic robot that follows the commanded twist
// and reports what its encoders and gyro would, and a sink that records the telemetry.
#include "fleetnav/robot_agent/agent.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/localization/dead_reckoning_localizer.hpp"
#include "kinematic_unicycle.hpp"

namespace fleetnav::agent {
namespace {

using ::testing::HasSubstr;
using testing::KinematicUnicycle;

constexpr double kPeriodS = 0.02;
constexpr int64_t kPeriodNs = 20'000'000;

/// A robot that does exactly what it is told: each tick integrates the last command over one
/// control period, rolls its wheels accordingly (v ∓ ω·L/2 over r) and reports cumulative
/// encoder ticks and the yaw rate on the gyro. Ends after max_ticks frames.
class KinematicHal : public RobotHal {
 public:
  KinematicHal(const RobotModel& model, uint64_t max_ticks)
      : model_(model), max_ticks_(max_ticks) {}

  /// A wall across the start's x axis at `x_m`: the robot cannot pass it (wheels and body
  /// stop) and, when `bumper` is true, its bumper closes once it is within 5 cm.
  void AddWall(double x_m, bool bumper) {
    wall_x_m_ = x_m;
    bumper_fitted_ = bumper;
  }

  absl::StatusOr<std::optional<SensorFrame>> NextFrame() override {
    if (issued_ > 0) {
      EXPECT_TRUE(answered_) << "no command for tick " << issued_ - 1;
      const double half_track = 0.5 * model_.track_m;
      KinematicUnicycle moved = robot_;
      moved.Step(command_, kPeriodS);
      if (!wall_x_m_ || moved.pose().x_m() < *wall_x_m_) {
        left_angle_rad_ += (command_.vx_mps - command_.yaw_rate_radps * half_track) /
                           model_.wheel_radius_m * kPeriodS;
        right_angle_rad_ += (command_.vx_mps + command_.yaw_rate_radps * half_track) /
                            model_.wheel_radius_m * kPeriodS;
        robot_ = moved;
      }
    }
    if (issued_ >= max_ticks_) return std::optional<SensorFrame>();
    SensorFrame frame;
    frame.tick = issued_;
    frame.stamp_ns = static_cast<int64_t>(issued_) * kPeriodNs;
    frame.control_period_s = kPeriodS;
    frame.encoders = {{"left", Ticks(left_angle_rad_)}, {"right", Ticks(right_angle_rad_)}};
    frame.imu.gyro_z_radps = command_.yaw_rate_radps;
    frame.bumper = bumper_fitted_ && wall_x_m_ && robot_.pose().x_m() >= *wall_x_m_ - 0.05;
    ++issued_;
    answered_ = false;
    return std::optional<SensorFrame>(frame);
  }

  absl::Status Send(const ActuatorCommand& command) override {
    EXPECT_EQ(command.tick, issued_ - 1);
    EXPECT_FALSE(answered_) << "two commands for tick " << command.tick;
    const Twist2* twist = std::get_if<Twist2>(&command.drive);
    if (twist == nullptr) return absl::InvalidArgumentError("expected a twist");
    command_ = *twist;
    answered_ = true;
    commands_.push_back(*twist);
    return absl::OkStatus();
  }

  Pose2 pose_in_start() const { return robot_.pose(); }
  const std::vector<Twist2>& commands() const { return commands_; }

 private:
  int64_t Ticks(double angle_rad) const {
    return static_cast<int64_t>(std::floor(angle_rad / (2.0 * kPi) * model_.encoder_ticks_per_rev));
  }

  RobotModel model_;
  uint64_t max_ticks_;
  uint64_t issued_ = 0;
  bool answered_ = true;
  Twist2 command_;
  double left_angle_rad_ = 0.0;
  double right_angle_rad_ = 0.0;
  KinematicUnicycle robot_;
  std::vector<Twist2> commands_;
  std::optional<double> wall_x_m_;
  bool bumper_fitted_ = false;
};

class RecordingSink : public TelemetrySink {
 public:
  void Publish(const Telemetry& telemetry) override { messages.push_back(telemetry); }
  std::vector<Telemetry> messages;
};

localization::DeadReckoningLocalizer Odometry(const RobotModel& model, const Pose2& start) {
  return localization::DeadReckoningLocalizer::Create(model, start).value();
}

/// An agent running `route` once on dead reckoning from `start`.
struct RouteRun {
  RouteRun(const RobotModel& model, RobotHal* hal, std::optional<Route> route,
           const Pose2& start = Pose2(), AgentParams params = {})
      : localizer(Odometry(model, start)),
        agent(RouteContext{model, std::nullopt, nullptr},
              AgentPorts{hal, &localizer, &sink, nullptr}, std::move(route), params) {}
  RecordingSink sink;
  localization::DeadReckoningLocalizer localizer;
  Agent agent;
};

Route FeedRoute() {
  Route route;
  route.name = "feed";
  route.map_id = "barn";
  route.actions = {{StraightAction{2.0, 0.25}, {}},
                   {TurnAction{DegToRad(90), 0.3}, {}},
                   {StraightAction{1.0, 0.25}, {}}};
  return route;
}

TEST(AgentTest, DrivesTheRouteAndReportsAtTenHertzOrMore) {
  const RobotModel model = LelyVectorModel();
  KinematicHal hal(model, 10000);
  const Pose2 initial(-5.5, 1.0, DegToRad(30));
  RouteRun run(model, &hal, FeedRoute(), initial);
  const RecordingSink& sink = run.sink;
  absl::StatusOr<AgentResult> result = run.agent.Run();
  ASSERT_TRUE(result.ok()) << result.status();
  EXPECT_EQ(result->state, ExecutionState::kSucceeded) << result->failure_reason;
  EXPECT_TRUE(result->failure_reason.empty());
  EXPECT_LT(result->ticks, 10000u);  // it returned once done, not when the HAL ran out

  // The robot really is at initial ∘ (2, 1, 90°), and so is the agent's estimate.
  const Pose2 target = initial * Pose2(2.0, 1.0, DegToRad(90));
  const Pose2 truth_in_map = initial * hal.pose_in_start();
  EXPECT_TRUE(truth_in_map.IsNear(target, 0.01, DegToRad(0.5))) << truth_in_map.DebugString();
  EXPECT_TRUE(result->final_pose_in_map.IsNear(truth_in_map, 0.005, DegToRad(0.2)))
      << result->final_pose_in_map.DebugString() << " vs " << truth_in_map.DebugString();

  // Telemetry: one message per ≤ 0.1 s of robot time from the first tick to the last.
  ASSERT_FALSE(sink.messages.empty());
  EXPECT_EQ(result->telemetry_sent, sink.messages.size());
  EXPECT_EQ(sink.messages.front().stamp_ns, 0);
  for (size_t i = 1; i < sink.messages.size(); ++i) {
    const Telemetry& previous = sink.messages[i - 1];
    const Telemetry& current = sink.messages[i];
    ASSERT_GT(current.stamp_ns, previous.stamp_ns) << i;
    ASSERT_LE(current.stamp_ns - previous.stamp_ns, 100'000'000) << i;  // ≥ 10 Hz
    ASSERT_EQ(current.sequence, previous.sequence + 1) << i;
    ASSERT_GE(current.job_progress_fraction, previous.job_progress_fraction - 1e-12) << i;
  }
  const int64_t last_tick_ns = static_cast<int64_t>(result->ticks - 1) * kPeriodNs;
  EXPECT_LE(last_tick_ns - sink.messages.back().stamp_ns, 100'000'000);
  const double rate_hz = static_cast<double>(sink.messages.size() - 1) /
                         (static_cast<double>(sink.messages.back().stamp_ns) * 1e-9);
  std::printf("[ figures  ] agent telemetry %.2f Hz of robot time over %llu ticks\n", rate_hz,
              static_cast<unsigned long long>(result->ticks));
  EXPECT_GE(rate_hz, 10.0);

  // Every message's map pose is initial ∘ its odometry pose; the last is the final pose.
  for (const Telemetry& t : sink.messages) {
    ASSERT_TRUE(t.pose_in_map.IsNear(initial * t.pose_in_odom, 1e-9, 1e-9));
  }
  const Telemetry& last = sink.messages.back();
  EXPECT_TRUE(last.pose_in_map.IsNear(result->final_pose_in_map, 1e-6, 1e-6));
  EXPECT_EQ(last.job_progress_fraction, 1.0);
  EXPECT_EQ(last.mode, NavigationMode::kIdle);
  EXPECT_TRUE(sink.messages.front().pose_in_map.IsNear(initial, 1e-12, 1e-12));
  // The route's modes showed up on the way.
  bool saw_turn = false, saw_straight = false;
  for (const Telemetry& t : sink.messages) {
    saw_turn = saw_turn || t.mode == NavigationMode::kTurn;
    saw_straight = saw_straight || t.mode == NavigationMode::kStraight;
  }
  EXPECT_TRUE(saw_turn);
  EXPECT_TRUE(saw_straight);

  // It settled: the last settle_ticks commands are standstill.
  const AgentParams defaults;
  ASSERT_GT(hal.commands().size(), static_cast<size_t>(defaults.settle_ticks));
  for (size_t i = hal.commands().size() - defaults.settle_ticks; i < hal.commands().size(); ++i) {
    EXPECT_EQ(hal.commands()[i].vx_mps, 0.0);
    EXPECT_EQ(hal.commands()[i].yaw_rate_radps, 0.0);
  }
  // Never a reverse command, never over the robot's limits.
  for (const Twist2& command : hal.commands()) {
    ASSERT_GE(command.vx_mps, 0.0);
    ASSERT_LE(command.vx_mps, model.limits.max_speed_mps);
    ASSERT_LE(std::abs(command.yaw_rate_radps), model.limits.max_yaw_rate_radps);
  }
}

TEST(AgentTest, UnsupportedActionFailsTheRouteBeforeTheRobotMoves) {
  const RobotModel model = LelyVectorModel();
  KinematicHal hal(model, 10000);
  Route route = FeedRoute();
  route.actions[1] = {DockAction{DockTarget::kTrolley, "t1"}, {}};
  RouteRun run(model, &hal, route);
  const RecordingSink& sink = run.sink;
  absl::StatusOr<AgentResult> result = run.agent.Run();
  ASSERT_TRUE(result.ok()) << result.status();
  EXPECT_EQ(result->state, ExecutionState::kFailed);
  EXPECT_THAT(result->failure_reason, HasSubstr("actions[1]"));
  EXPECT_LT(result->ticks, 10000u);
  EXPECT_NEAR(hal.pose_in_start().x_m(), 0.0, 1e-9);  // nothing half-executed
  ASSERT_FALSE(result->events.empty());
  EXPECT_EQ(result->events.back().type, JobEventType::kFailed);
  // The robot was told to stop when the route failed.
  EXPECT_EQ(hal.commands().back().vx_mps, 0.0);
  EXPECT_EQ(hal.commands().back().yaw_rate_radps, 0.0);
  EXPECT_NEAR(sink.messages.back().velocity.vx_mps, 0.0, 1e-9);
}

TEST(AgentTest, WithoutARouteRunsUntilTheHardwareEnds) {
  const RobotModel model = LelyVectorModel();
  KinematicHal hal(model, 123);
  RouteRun run(model, &hal, std::nullopt);
  const RecordingSink& sink = run.sink;
  absl::StatusOr<AgentResult> result = run.agent.Run();
  ASSERT_TRUE(result.ok()) << result.status();
  EXPECT_EQ(result->ticks, 123u);
  EXPECT_EQ(result->state, ExecutionState::kRunning);
  EXPECT_TRUE(result->final_pose_in_map.IsNear(Pose2(), 1e-12, 1e-12));
  EXPECT_GE(sink.messages.size(), 123u * kPeriodS * 10.0);
}

// A robot that drives into something stops at once, reports BUMPER, and its action fails
// with the reason: no action "succeeds" while the robot is stuck.
TEST(AgentTest, BumperStopsTheRobotAndFailsTheAction) {
  const RobotModel model = LelyVectorModel();
  KinematicHal hal(model, 10000);
  hal.AddWall(1.0, /*bumper=*/true);
  RouteRun run(model, &hal, FeedRoute());
  absl::StatusOr<AgentResult> result = run.agent.Run();
  ASSERT_TRUE(result.ok()) << result.status();
  EXPECT_EQ(result->state, ExecutionState::kFailed);
  EXPECT_EQ(result->safety_stop, SafetyStop::kBumper);
  EXPECT_THAT(result->failure_reason, HasSubstr("actions[0] (straight): bumper pressed"));
  EXPECT_LT(hal.pose_in_start().x_m(), 1.0);
  bool bumper_event = false;
  for (const JobEvent& e : result->events) bumper_event |= e.type == JobEventType::kBumper;
  EXPECT_TRUE(bumper_event);
  EXPECT_EQ(result->events.back().type, JobEventType::kFailed);
  EXPECT_EQ(hal.commands().back().vx_mps, 0.0);
  EXPECT_EQ(run.sink.messages.back().mode, NavigationMode::kFault);
}

TEST(AgentTest, StallWithoutBumperFailsAfterTwoSeconds) {
  const RobotModel model = LelyVectorModel();
  KinematicHal hal(model, 10000);
  hal.AddWall(1.0, /*bumper=*/false);
  RouteRun run(model, &hal, FeedRoute());
  absl::StatusOr<AgentResult> result = run.agent.Run();
  ASSERT_TRUE(result.ok()) << result.status();
  EXPECT_EQ(result->state, ExecutionState::kFailed);
  EXPECT_EQ(result->safety_stop, SafetyStop::kStall);
  EXPECT_THAT(result->failure_reason, HasSubstr("actions[0] (straight): stalled"));
  // It drove ~1 m (4 s at 0.25 m/s), then stalled for 2 s: well under 10 s of ticks.
  EXPECT_LT(result->ticks * kPeriodS, 10.0);
  EXPECT_EQ(hal.commands().back().vx_mps, 0.0);
}

/// A JobChannel with one assignment and a record of the events. Traffic clearance: the first
/// poll clears up to `first_cleared`; poll `clear_all_at` clears every action.
class OneJobChannel : public JobChannel {
 public:
  explicit OneJobChannel(JobAssignment assignment, int first_cleared = 1000, int clear_all_at = 0)
      : assignment_(std::move(assignment)),
        first_cleared_(first_cleared),
        clear_all_at_(clear_all_at) {}
  std::optional<JobAssignment> TakeAssignment() override { return std::exchange(assignment_, {}); }
  std::vector<JobCommand> TakeCommands() override {
    ++polls;
    const std::string job_id = "job-1";
    if (polls == 1) return {JobCommand{JobCommandType::kClearance, job_id, "", first_cleared_}};
    if (polls == clear_all_at_) return {JobCommand{JobCommandType::kClearance, job_id, "", 1000}};
    return {};
  }
  void ReportEvent(const JobEvent& event) override {
    events.push_back(event);
    event_polls.push_back(polls);
  }
  void SetCurrentJob(const std::string&) override {}
  std::vector<JobEvent> events;
  std::vector<int> event_polls;  ///< the poll count when each event came
  int polls = 0;

 private:
  std::optional<JobAssignment> assignment_;
  int first_cleared_;
  int clear_all_at_;
};

/// A SiteSource that has map "barn" v3 with marker set v2 only.
class OneSite : public SiteSource {
 public:
  absl::StatusOr<SiteData> Load(const std::string& map_id, uint32_t map_version,
                                uint32_t marker_set_version) override {
    ++loads;
    if (map_id != "barn" || map_version != 3) return absl::NotFoundError("no such map version");
    SiteData site{
        map_id, map_version, marker_set_version,
        std::make_shared<const OccupancyGrid>(
            OccupancyGrid::Filled(10, 10, 1.0, Pose2(), OccupancyGrid::kFreeValue).value()),
        MarkerSet{}};
    return site;
  }
  int loads = 0;
};

JobAssignment FeedJob(uint32_t map_version) {
  JobAssignment assignment;
  assignment.job.job_id = "job-1";
  assignment.job.map_id = "barn";
  assignment.route = std::make_shared<const Route>(FeedRoute());
  assignment.map_version = map_version;
  assignment.marker_set_version = 2;
  return assignment;
}

// In job mode the job's map and marker set, at the versions the route was validated against,
// are loaded and the robot localizes on them from where it stands.
TEST(AgentTest, JobBringsItsSiteAndTheAgentLocalizesOnIt) {
  const RobotModel model = LelyVectorModel();
  KinematicHal hal(model, 10000);
  RecordingSink sink;
  OneJobChannel jobs(FeedJob(3));
  OneSite sites;
  const Pose2 start(2.0, 3.0, 0.0);
  localization::DeadReckoningLocalizer initial = Odometry(model, start);
  std::vector<SiteData> made_for;
  AgentPorts ports{
      &hal,
      &initial,
      &sink,
      &jobs,
      &sites,
      [&](const SiteData& site,
          const Pose2& from) -> absl::StatusOr<std::unique_ptr<localization::Localizer>> {
        made_for.push_back(site);
        EXPECT_TRUE(from.IsNear(start, 1e-6, 1e-6)) << from.DebugString();
        return std::make_unique<localization::DeadReckoningLocalizer>(Odometry(model, from));
      }};
  Agent agent(RouteContext{model, std::nullopt, nullptr}, ports, std::nullopt,
              AgentParams{.max_jobs = 1});
  absl::StatusOr<AgentResult> result = agent.Run();
  ASSERT_TRUE(result.ok()) << result.status();
  EXPECT_EQ(sites.loads, 1);
  ASSERT_EQ(made_for.size(), 1u);
  EXPECT_EQ(made_for[0].map_version, 3u);
  EXPECT_EQ(made_for[0].marker_set_version, 2u);
  ASSERT_FALSE(jobs.events.empty());
  EXPECT_EQ(jobs.events.back().type, JobEventType::kSucceeded) << jobs.events.back().reason;
  EXPECT_TRUE(
      result->final_pose_in_map.IsNear(start * Pose2(2.0, 1.0, DegToRad(90)), 0.02, DegToRad(1)));
}

// Traffic coordination: an action starts only once cleared. Cleared up to action 0, the robot
// drives it, reports it finished at once and stands until the rest is cleared.
TEST(AgentTest, JobActionsWaitForTheirTrafficClearance) {
  const RobotModel model = LelyVectorModel();
  KinematicHal hal(model, 10000);
  RecordingSink sink;
  OneJobChannel jobs(FeedJob(3), /*first_cleared=*/0, /*clear_all_at=*/2000);
  OneSite sites;
  localization::DeadReckoningLocalizer initial = Odometry(model, Pose2());
  AgentPorts ports{
      &hal,
      &initial,
      &sink,
      &jobs,
      &sites,
      [&](const SiteData&,
          const Pose2& from) -> absl::StatusOr<std::unique_ptr<localization::Localizer>> {
        return std::make_unique<localization::DeadReckoningLocalizer>(Odometry(model, from));
      }};
  Agent agent(RouteContext{model, std::nullopt, nullptr}, ports, std::nullopt,
              AgentParams{.max_jobs = 1});
  absl::StatusOr<AgentResult> result = agent.Run();
  ASSERT_TRUE(result.ok()) << result.status();
  int finished0_poll = -1;
  int started1_poll = -1;
  for (size_t i = 0; i < jobs.events.size(); ++i) {
    const JobEvent& e = jobs.events[i];
    if (e.type == JobEventType::kActionFinished && e.action_index == 0)
      finished0_poll = jobs.event_polls[i];
    if (e.type == JobEventType::kActionStarted && e.action_index == 1)
      started1_poll = jobs.event_polls[i];
  }
  ASSERT_GT(finished0_poll, 0);
  EXPECT_LT(finished0_poll, 2000);  // finished before the clearance, not when the next started
  EXPECT_GE(started1_poll, 2000);   // action 1 began only once cleared
  EXPECT_EQ(jobs.events.back().type, JobEventType::kSucceeded) << jobs.events.back().reason;
  EXPECT_TRUE(result->final_pose_in_map.IsNear(Pose2(2.0, 1.0, DegToRad(90)), 0.02, DegToRad(1)));
}

TEST(AgentTest, JobWhoseSiteCannotBeLoadedFailsBeforeMoving) {
  const RobotModel model = LelyVectorModel();
  KinematicHal hal(model, 10000);
  RecordingSink sink;
  OneJobChannel jobs(FeedJob(7));
  OneSite sites;
  localization::DeadReckoningLocalizer initial = Odometry(model, Pose2());
  AgentPorts ports{&hal,
                   &initial,
                   &sink,
                   &jobs,
                   &sites,
                   [&](const SiteData&,
                       const Pose2&) -> absl::StatusOr<std::unique_ptr<localization::Localizer>> {
                     ADD_FAILURE() << "no site, no localizer";
                     return absl::InternalError("unreachable");
                   }};
  Agent agent(RouteContext{model, std::nullopt, nullptr}, ports, std::nullopt,
              AgentParams{.max_jobs = 1});
  absl::StatusOr<AgentResult> result = agent.Run();
  ASSERT_TRUE(result.ok()) << result.status();
  ASSERT_FALSE(jobs.events.empty());
  EXPECT_EQ(jobs.events.back().type, JobEventType::kFailed);
  EXPECT_THAT(jobs.events.back().reason, HasSubstr("map barn v7 could not be loaded"));
  EXPECT_NEAR(hal.pose_in_start().x_m(), 0.0, 1e-9);
}

class FailingHal : public RobotHal {
 public:
  absl::StatusOr<std::optional<SensorFrame>> NextFrame() override {
    return absl::UnavailableError("bus down");
  }
  absl::Status Send(const ActuatorCommand&) override { return absl::OkStatus(); }
};

TEST(AgentTest, HalErrorsAndBadParamsPropagate) {
  const RobotModel model = LelyVectorModel();
  FailingHal failing;
  RouteRun broken(model, &failing, FeedRoute());
  EXPECT_EQ(broken.agent.Run().status().code(), absl::StatusCode::kUnavailable);

  KinematicHal hal(model, 10);
  RouteRun slow(model, &hal, FeedRoute(), Pose2(), AgentParams{.telemetry_period_s = 0.5});
  EXPECT_EQ(slow.agent.Run().status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_TRUE(slow.sink.messages.empty());
}

}  // namespace
}  // namespace fleetnav::agent
