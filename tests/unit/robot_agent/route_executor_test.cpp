#include "fleetnav/robot_agent/route_executor.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "fleetnav/core/angles.hpp"
#include "kinematic_unicycle.hpp"

namespace fleetnav::agent {
namespace {

using ::testing::HasSubstr;
using testing::KinematicUnicycle;

constexpr double kDt = 0.02;
constexpr int kMaxSteps = 20000;

RouteAction Act(ActionParams params, EndCondition end = {}) { return RouteAction{params, end}; }

Route MakeRoute(std::vector<RouteAction> actions) {
  Route route;
  route.name = "test-route";
  route.map_id = "barn";
  route.actions = std::move(actions);
  return route;
}

struct RunResult {
  ExecutionState state = ExecutionState::kRunning;
  int steps = 0;
  std::vector<ExecutorOutput> outputs;
  KinematicUnicycle robot;
};

RunResult RunOnUnicycle(RouteExecutor& executor, const Pose2& start = Pose2()) {
  RunResult result{.robot = KinematicUnicycle(start)};
  for (; result.steps < kMaxSteps; ++result.steps) {
    const ExecutorOutput out = executor.Step(result.robot.pose(), kDt);
    result.outputs.push_back(out);
    if (out.state != ExecutionState::kRunning) {
      result.state = out.state;
      break;
    }
    result.robot.Step(out.command, kDt);
  }
  return result;
}

TEST(RouteExecutorTest, StraightTurnStraightEndsWhereTheRouteSays) {
  RouteExecutor executor(
      MakeRoute({Act(StraightAction{2.0, 0.25}), Act(TurnAction{DegToRad(90), 0.3}),
                 Act(StraightAction{1.0, 0.25})}));
  const RunResult run = RunOnUnicycle(executor);
  ASSERT_EQ(run.state, ExecutionState::kSucceeded) << executor.failure();
  EXPECT_EQ(executor.state(), ExecutionState::kSucceeded);
  EXPECT_TRUE(executor.failure().ok());
  const Pose2 end = run.robot.pose();
  EXPECT_NEAR(end.x_m(), 2.0, 0.01);
  EXPECT_NEAR(end.y_m(), 1.0, 0.01);
  EXPECT_NEAR(RadToDeg(end.yaw_rad()), 90.0, 0.5);

  // Modes and action indices follow the route; progress never falls and ends at 1.
  double last_progress = 0.0;
  int last_index = 0;
  bool saw_turn = false;
  for (size_t i = 0; i < run.outputs.size(); ++i) {
    const ExecutorOutput& out = run.outputs[i];
    ASSERT_GE(out.progress_fraction, last_progress - 1e-12) << "step " << i;
    ASSERT_LE(out.progress_fraction, 1.0);
    last_progress = out.progress_fraction;
    if (out.state != ExecutionState::kRunning) break;
    ASSERT_GE(out.action_index, last_index) << "step " << i;
    last_index = out.action_index;
    if (out.action_index == 1) {
      saw_turn = true;
      EXPECT_EQ(out.mode, NavigationMode::kTurn);
      EXPECT_EQ(out.command.vx_mps, 0.0);
    } else {
      EXPECT_EQ(out.mode, NavigationMode::kStraight);
      EXPECT_GE(out.command.vx_mps, 0.0);
    }
  }
  EXPECT_TRUE(saw_turn);
  EXPECT_EQ(last_index, 2);
  EXPECT_EQ(run.outputs.back().progress_fraction, 1.0);
  EXPECT_EQ(run.outputs.back().mode, NavigationMode::kIdle);
  EXPECT_EQ(run.outputs.back().command.vx_mps, 0.0);
  EXPECT_EQ(run.outputs.back().command.yaw_rate_radps, 0.0);

  // Once done it stays done and commands a standstill.
  const ExecutorOutput after = executor.Step(run.robot.pose(), kDt);
  EXPECT_EQ(after.state, ExecutionState::kSucceeded);
  EXPECT_EQ(after.progress_fraction, 1.0);
  EXPECT_EQ(after.command.vx_mps, 0.0);
}

TEST(RouteExecutorTest, RouteFromAnOffsetStartIsRelative) {
  RouteExecutor executor(
      MakeRoute({Act(TurnAction{DegToRad(-270), 0.4}), Act(StraightAction{1.5, 0.4})}));
  const Pose2 start(3.0, -1.0, DegToRad(30));
  const RunResult run = RunOnUnicycle(executor, start);
  ASSERT_EQ(run.state, ExecutionState::kSucceeded) << executor.failure();
  // -270° from 30° is heading 120°, then 1.5 m along it.
  const Pose2 expected = start * Pose2(0, 0, DegToRad(-270)) * Pose2(1.5, 0, 0);
  EXPECT_TRUE(run.robot.pose().IsNear(expected, 0.01, DegToRad(0.5)))
      << run.robot.pose().DebugString() << " vs " << expected.DebugString();
  EXPECT_NEAR(RadToDeg(run.robot.unwrapped_yaw_rad()), 30.0 - 270.0, 0.5);
}

TEST(RouteExecutorTest, FenceNavigationFailsNamingTheAction) {
  RouteExecutor executor(MakeRoute({Act(StraightAction{0.5, 0.25}),
                                    Act(FenceNavigationAction{Side::kLeft, 0.5, 10.0, 0.25}),
                                    Act(StraightAction{1.0, 0.25})}));
  const RunResult run = RunOnUnicycle(executor);
  ASSERT_EQ(run.state, ExecutionState::kFailed);
  EXPECT_EQ(executor.state(), ExecutionState::kFailed);
  EXPECT_EQ(executor.failure().code(), absl::StatusCode::kFailedPrecondition) << executor.failure();
  EXPECT_THAT(std::string(executor.failure().message()), HasSubstr("actions[1]"));
  EXPECT_THAT(std::string(executor.failure().message()), HasSubstr("fence_navigation"));
  // The first straight was driven, the fence part was not, and the robot is told to stop.
  EXPECT_NEAR(run.robot.pose().x_m(), 0.5, 0.005);
  EXPECT_EQ(run.outputs.back().mode, NavigationMode::kFault);
  EXPECT_EQ(run.outputs.back().command.vx_mps, 0.0);
  EXPECT_EQ(run.outputs.back().command.yaw_rate_radps, 0.0);
  EXPECT_EQ(executor.Step(run.robot.pose(), kDt).state, ExecutionState::kFailed);
}

TEST(RouteExecutorTest, UnsupportedFirstActionFailsAtOnce) {
  RouteExecutor executor(MakeRoute({Act(DockAction{DockTarget::kCharger, "pole"})}));
  const ExecutorOutput out = executor.Step(Pose2(), kDt);
  EXPECT_EQ(out.state, ExecutionState::kFailed);
  EXPECT_EQ(executor.failure().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_THAT(std::string(executor.failure().message()), HasSubstr("actions[0]"));
}

TEST(RouteExecutorTest, EndConditionNeedingSensingFails) {
  RouteExecutor executor(
      MakeRoute({Act(StraightAction{1.0, 0.25}),
                 Act(StraightAction{3.0, 0.25}, {EndConditionKind::kMarkerDetected, 4})}));
  const RunResult run = RunOnUnicycle(executor);
  ASSERT_EQ(run.state, ExecutionState::kFailed);
  EXPECT_EQ(executor.failure().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_THAT(std::string(executor.failure().message()), HasSubstr("actions[1]"));
  EXPECT_THAT(std::string(executor.failure().message()), HasSubstr("marker"));
}

TEST(RouteExecutorTest, EmptyRouteSucceedsAtOnce) {
  RouteExecutor executor(MakeRoute({}));
  const ExecutorOutput out = executor.Step(Pose2(), kDt);
  EXPECT_EQ(out.state, ExecutionState::kSucceeded);
  EXPECT_EQ(out.progress_fraction, 1.0);
}

}  // namespace
}  // namespace fleetnav::agent
