#include "fleetnav/robot_agent/route_executor.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/robot_agent/mode_factory.hpp"
#include "kinematic_unicycle.hpp"

namespace fleetnav::agent {
namespace {

using ::testing::HasSubstr;
using testing::KinematicUnicycle;

constexpr double kDt = 0.02;
constexpr int kMaxSteps = 20000;

RouteAction Act(ActionParams params, EndCondition end = {}) { return RouteAction{params, end}; }

RouteContext Lely(std::optional<MarkerSet> markers = std::nullopt) {
  return RouteContext{LelyVectorModel(), std::move(markers), nullptr};
}

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

RunResult RunOnUnicycle(RouteExecutor& executor, const Pose2& start = Pose2(),
                        double marker_at_x_m = -1e9, int marker_id = -1) {
  RunResult result{.robot = KinematicUnicycle(start)};
  bool marker_seen = false;
  for (; result.steps < kMaxSteps; ++result.steps) {
    std::vector<int> markers;
    if (!marker_seen && result.robot.pose().x_m() >= marker_at_x_m) {
      markers.push_back(marker_id);
      marker_seen = true;
    }
    const ExecutorOutput out = executor.Step(OdometryInput(result.robot.pose(), kDt), markers);
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
                 Act(StraightAction{1.0, 0.25})}),
      Lely());
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
  const ExecutorOutput after = executor.Step(OdometryInput(run.robot.pose(), kDt));
  EXPECT_EQ(after.state, ExecutionState::kSucceeded);
  EXPECT_EQ(after.progress_fraction, 1.0);
  EXPECT_EQ(after.command.vx_mps, 0.0);
}

TEST(RouteExecutorTest, ARobotHeldAtASegmentGateStandsBeforeItUntilClearedFurther) {
  // A 6 m straight east; traffic coordination clears it up to a gate at x = 3 m.
  RouteExecutor executor(MakeRoute({Act(StraightAction{6.0, 0.5})}), Lely());
  executor.SetClearedUpTo(0);
  executor.SetHold(SegmentHold{0, 0, Pose2(3.0, 0.0, 0.0)});
  KinematicUnicycle robot;
  ExecutorOutput out;
  for (int step = 0; step < 3000; ++step) {  // 60 s: long enough to have driven all 6 m
    out = executor.Step(OdometryInput(robot.pose(), kDt));
    robot.Step(out.command, kDt);
  }
  EXPECT_EQ(out.state, ExecutionState::kRunning);
  EXPECT_FALSE(out.waiting);                   // not done with the action: not reported finished
  EXPECT_EQ(out.mode, NavigationMode::kIdle);  // standing held: counted as waiting
  EXPECT_LT(robot.pose().x_m(), 3.0);
  EXPECT_GT(robot.pose().x_m(), 2.7);
  EXPECT_TRUE(ReachedGate(Pose2(3.0, 0.0, 0.0), robot.pose().translation()));
  // Cleared to the end of the action: it drives on and ends where the route says.
  executor.SetHold(std::nullopt);
  RunResult rest = RunOnUnicycle(executor, robot.pose());
  EXPECT_EQ(rest.state, ExecutionState::kSucceeded);
  EXPECT_NEAR(rest.robot.pose().x_m(), 6.0, 0.05);
}

TEST(RouteExecutorTest, AGateOfAnotherActionOrBehindTheRobotsWayDoesNotHoldIt) {
  // The hold names action 1: action 0 drives whole.
  RouteExecutor later(MakeRoute({Act(StraightAction{2.0, 0.5}), Act(StraightAction{2.0, 0.5})}),
                      Lely());
  later.SetClearedUpTo(1);
  later.SetHold(SegmentHold{1, 0, Pose2(1.0, 0.0, 0.0)});
  KinematicUnicycle robot;
  for (int step = 0; step < 1000 && later.action_index() < 1; ++step) {
    robot.Step(later.Step(OdometryInput(robot.pose(), kDt)).command, kDt);
  }
  EXPECT_NEAR(robot.pose().x_m(), 2.0, 0.05);
  // A gate facing the other way (a path that comes back past it) is not this way's gate.
  RouteExecutor back(MakeRoute({Act(StraightAction{4.0, 0.5})}), Lely());
  back.SetClearedUpTo(0);
  back.SetHold(SegmentHold{0, 0, Pose2(2.0, 0.5, kPi)});
  EXPECT_EQ(RunOnUnicycle(back).state, ExecutionState::kSucceeded);
}

TEST(RouteExecutorTest, RouteFromAnOffsetStartIsRelative) {
  RouteExecutor executor(
      MakeRoute({Act(TurnAction{DegToRad(-270), 0.4}), Act(StraightAction{1.5, 0.4})}), Lely());
  const Pose2 start(3.0, -1.0, DegToRad(30));
  const RunResult run = RunOnUnicycle(executor, start);
  ASSERT_EQ(run.state, ExecutionState::kSucceeded) << executor.failure();
  // -270° from 30° is heading 120°, then 1.5 m along it.
  const Pose2 expected = start * Pose2(0, 0, DegToRad(-270)) * Pose2(1.5, 0, 0);
  EXPECT_TRUE(run.robot.pose().IsNear(expected, 0.01, DegToRad(0.5)))
      << run.robot.pose().DebugString() << " vs " << expected.DebugString();
  EXPECT_NEAR(RadToDeg(run.robot.unwrapped_yaw_rad()), 30.0 - 270.0, 0.5);
}

// A route with an action this agent cannot run is refused before the robot moves, naming the
// action: nothing is half-executed.
TEST(RouteExecutorTest, UnsupportedActionRefusesTheWholeRouteBeforeMoving) {
  RouteExecutor executor(
      MakeRoute({Act(StraightAction{0.5, 0.25}), Act(DockAction{DockTarget::kTrolley, "t1"}),
                 Act(StraightAction{1.0, 0.25})}),
      Lely());
  EXPECT_EQ(executor.state(), ExecutionState::kFailed);
  const ExecutorOutput out = executor.Step(OdometryInput(Pose2(), kDt));
  EXPECT_EQ(out.state, ExecutionState::kFailed);
  EXPECT_EQ(out.mode, NavigationMode::kFault);
  EXPECT_EQ(out.command.vx_mps, 0.0);
  EXPECT_EQ(executor.failure().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_THAT(std::string(executor.failure().message()), HasSubstr("actions[1]"));
  EXPECT_THAT(std::string(executor.failure().message()), HasSubstr("dock"));
}

TEST(RouteExecutorTest, FenceLegOnARobotWithoutUltrasonicsIsRefused) {
  RouteExecutor executor(MakeRoute({Act(FenceNavigationAction{Side::kLeft, 0.5, 10.0, 0.25})}),
                         RouteContext{MecanumPlatformModel(), std::nullopt, nullptr});
  EXPECT_EQ(executor.state(), ExecutionState::kFailed);
  EXPECT_THAT(std::string(executor.failure().message()), HasSubstr("actions[0]"));
  EXPECT_THAT(std::string(executor.failure().message()), HasSubstr("ultrasonic"));
}

TEST(RouteExecutorTest, ATurnInPlaceOnAnAckermannRobotIsRefused) {
  RouteExecutor executor(
      MakeRoute({Act(StraightAction{1.0, 0.25}), Act(TurnAction{DegToRad(90), 0.3})}),
      RouteContext{AckermannDeliveryModel(), std::nullopt, nullptr});
  EXPECT_EQ(executor.state(), ExecutionState::kFailed);
  EXPECT_EQ(executor.failure().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_THAT(std::string(executor.failure().message()), HasSubstr("actions[1] (turn)"));
  EXPECT_THAT(std::string(executor.failure().message()), HasSubstr("cannot turn in place"));
}

// What each kind says it runs: the dispatcher sends a job only to robots that advertise every
// action type of its route.
TEST(RouteExecutorTest, EachKindAdvertisesWhatItsSensorsAndDriveAllow) {
  using ::testing::ElementsAre;
  EXPECT_THAT(SupportedActionTypes(LelyVectorModel()),
              ElementsAre("straight", "turn", "fence_navigation", "stripe_navigation", "dock",
                          "free_navigation"));
  EXPECT_THAT(SupportedActionTypes(MecanumPlatformModel()),
              ElementsAre("straight", "turn", "free_navigation", "move", "dock", "undock"));
  EXPECT_THAT(SupportedActionTypes(AckermannDeliveryModel()),
              ElementsAre("straight", "free_navigation"));
}

TEST(RouteExecutorTest, MarkerEndWithoutAMarkerSetIsRefused) {
  RouteExecutor executor(
      MakeRoute({Act(StraightAction{1.0, 0.25}),
                 Act(StraightAction{3.0, 0.25}, {EndConditionKind::kMarkerDetected, 4})}),
      Lely());
  EXPECT_EQ(executor.state(), ExecutionState::kFailed);
  EXPECT_EQ(executor.failure().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_THAT(std::string(executor.failure().message()), HasSubstr("actions[1]"));
  EXPECT_THAT(std::string(executor.failure().message()), HasSubstr("marker set"));
}

MarkerSet OneMarker(int id) {
  MarkerSet markers;
  markers.map_id = "barn";
  StripeMarker m;
  m.id = id;
  m.position_m = Eigen::Vector2d(1.2, 0.0);
  m.yaw_rad = DegToRad(-90);
  m.length_m = 0.6;
  markers.markers.push_back(m);
  return markers;
}

// A straight that ends on a marker ends when the localizer reports the marker, not at its
// distance; the next action starts there.
TEST(RouteExecutorTest, StraightEndsOnTheDetectedMarker) {
  RouteExecutor executor(
      MakeRoute({Act(StraightAction{5.0, 0.25}, {EndConditionKind::kMarkerDetected, 7}),
                 Act(TurnAction{DegToRad(90), 0.3})}),
      Lely(OneMarker(7)));
  ASSERT_EQ(executor.state(), ExecutionState::kRunning) << executor.failure();
  const RunResult run = RunOnUnicycle(executor, Pose2(), /*marker_at_x_m=*/1.2, 7);
  ASSERT_EQ(run.state, ExecutionState::kSucceeded) << executor.failure();
  EXPECT_NEAR(run.robot.pose().x_m(), 1.2, 0.1);  // stopped near the marker, not at 5 m
  EXPECT_NEAR(RadToDeg(run.robot.pose().yaw_rad()), 90.0, 1.0);
}

TEST(RouteExecutorTest, MarkerNeverSeenFailsAtTheActionsDistance) {
  RouteExecutor executor(
      MakeRoute({Act(StraightAction{1.0, 0.25}, {EndConditionKind::kMarkerDetected, 7})}),
      Lely(OneMarker(7)));
  const RunResult run = RunOnUnicycle(executor);
  ASSERT_EQ(run.state, ExecutionState::kFailed);
  EXPECT_NEAR(run.robot.pose().x_m(), 1.0, 0.01);
  EXPECT_THAT(std::string(executor.failure().message()), HasSubstr("marker 7 was not detected"));
}

TEST(RouteExecutorTest, AbortFailsTheCurrentActionAndStops) {
  RouteExecutor executor(
      MakeRoute({Act(StraightAction{1.0, 0.25}), Act(StraightAction{1.0, 0.25})}), Lely());
  KinematicUnicycle robot;
  for (int i = 0; i < 50; ++i)
    robot.Step(executor.Step(OdometryInput(robot.pose(), kDt)).command, kDt);
  executor.Abort(absl::AbortedError("bumper pressed"));
  const ExecutorOutput out = executor.Step(OdometryInput(robot.pose(), kDt));
  EXPECT_EQ(out.state, ExecutionState::kFailed);
  EXPECT_EQ(out.command.vx_mps, 0.0);
  EXPECT_EQ(std::string(executor.failure().message()), "actions[0] (straight): bumper pressed");
}

TEST(RouteExecutorTest, EmptyRouteSucceedsAtOnce) {
  RouteExecutor executor(MakeRoute({}), Lely());
  const ExecutorOutput out = executor.Step(OdometryInput(Pose2(), kDt));
  EXPECT_EQ(out.state, ExecutionState::kSucceeded);
  EXPECT_EQ(out.progress_fraction, 1.0);
}

// An agent restarted 1.2 m into a 2 m straight drives the 0.8 m left of it, then the rest of
// the route: the robot ends where the route says, not 1.2 m beyond.
TEST(RouteExecutorTest, ResumedMidStraightDrivesOnlyWhatIsLeft) {
  const Pose2 where(1.2, 0.0, 0.0);
  RouteExecutor executor(
      MakeRoute({Act(TurnAction{DegToRad(10), 0.3}), Act(StraightAction{2.0, 0.25}),
                 Act(TurnAction{DegToRad(90), 0.3}), Act(StraightAction{1.0, 0.25})}),
      Lely(), {}, where, RoutePosition{1, 0.6});
  ASSERT_TRUE(executor.failure().ok()) << executor.failure();
  const RunResult run = RunOnUnicycle(executor, where);
  ASSERT_EQ(run.state, ExecutionState::kSucceeded) << executor.failure();
  EXPECT_NEAR(run.robot.pose().x_m(), 2.0, 0.02);
  EXPECT_NEAR(run.robot.pose().y_m(), 1.0, 0.02);
  EXPECT_NEAR(RadToDeg(run.robot.pose().yaw_rad()), 90.0, 0.5);
  // The resumed action reports its progress from 60 %; action 0 is never run again.
  ASSERT_FALSE(run.outputs.empty());
  EXPECT_EQ(run.outputs.front().action_index, 1);
  EXPECT_GE(run.outputs.front().action_fraction, 0.6);
  EXPECT_GE(run.outputs.front().progress_fraction, (1 + 0.6) / 4.0 - 1e-9);
  for (const ExecutorOutput& out : run.outputs) EXPECT_NE(out.action_index, 0);
}

// A turn interrupted at 75 % turns the last quarter.
TEST(RouteExecutorTest, ResumedMidTurnTurnsTheRest) {
  const Pose2 where(0.0, 0.0, DegToRad(67.5));
  RouteExecutor executor(MakeRoute({Act(TurnAction{DegToRad(90), 0.3})}), Lely(), {}, where,
                         RoutePosition{0, 0.75});
  const RunResult run = RunOnUnicycle(executor, where);
  ASSERT_EQ(run.state, ExecutionState::kSucceeded) << executor.failure();
  EXPECT_NEAR(RadToDeg(run.robot.pose().yaw_rad()), 90.0, 0.5);
}

// Nothing left of the last action: the route has succeeded without moving; nothing left of
// another: the next action waits for its clearance.
TEST(RouteExecutorTest, ResumedAtTheEndOfAnActionGoesOnWithTheNext) {
  RouteExecutor done(MakeRoute({Act(StraightAction{2.0, 0.25})}), Lely(), {}, Pose2(2, 0, 0),
                     RoutePosition{0, 1.0});
  EXPECT_EQ(done.state(), ExecutionState::kSucceeded);

  RouteExecutor next(MakeRoute({Act(StraightAction{2.0, 0.25}), Act(StraightAction{1.0, 0.25})}),
                     Lely(), {}, Pose2(2, 0, 0), RoutePosition{0, 1.0});
  next.SetClearedUpTo(0);
  const ExecutorOutput held = next.Step(OdometryInput(Pose2(2, 0, 0), kDt));
  EXPECT_TRUE(held.waiting);
  EXPECT_EQ(held.action_index, 0);
  EXPECT_EQ(held.command.vx_mps, 0.0);
  next.SetClearedUpTo(1);
  const RunResult run = RunOnUnicycle(next, Pose2(2, 0, 0));
  ASSERT_EQ(run.state, ExecutionState::kSucceeded);
  EXPECT_NEAR(run.robot.pose().x_m(), 3.0, 0.02);
}

TEST(RouteExecutorTest, ResumePositionOutsideTheRouteFailsIt) {
  RouteExecutor executor(MakeRoute({Act(StraightAction{2.0, 0.25})}), Lely(), {}, Pose2(),
                         RoutePosition{3, 0.5});
  EXPECT_EQ(executor.state(), ExecutionState::kFailed);
  EXPECT_THAT(executor.failure().message(), HasSubstr("action 3 is not in route"));
}

/// A 14 x 6 m room (0.1 m cells) walled round, for free navigation.
RouteContext OmniInRoom() {
  OccupancyGrid grid =
      OccupancyGrid::Filled(140, 60, 0.1, Pose2(), OccupancyGrid::kFreeValue).value();
  for (int y = 0; y < 60; ++y) {
    for (int x = 0; x < 140; ++x) {
      if (x == 0 || y == 0 || x == 139 || y == 59) {
        grid.SetValue({x, y}, OccupancyGrid::kOccupiedValue);
      }
    }
  }
  return RouteContext{MecanumPlatformModel(), std::nullopt,
                      std::make_shared<const OccupancyGrid>(std::move(grid))};
}

/// Drives `executor` on an ideal omnidirectional body from `start`; `at_step(i, pose)` runs
/// before each tick with the progress so far. Returns the poses driven.
template <typename AtStep>
std::vector<Pose2> DriveOmni(RouteExecutor& executor, const Pose2& start, AtStep at_step) {
  std::vector<Pose2> poses{start};
  double progress = 0.0;
  for (int i = 0; i < kMaxSteps; ++i) {
    at_step(progress, poses.back());
    const ExecutorOutput out = executor.Step(OdometryInput(poses.back(), kDt));
    if (out.state != ExecutionState::kRunning) break;
    progress = out.progress_fraction;
    poses.push_back(testing::MovedOmni(poses.back(), out.command, kDt));
  }
  return poses;
}

double ClosestM(const std::vector<Pose2>& poses, const Eigen::Vector2d& point) {
  double closest_m = 1e9;
  for (const Pose2& p : poses) closest_m = std::min(closest_m, (p.translation() - point).norm());
  return closest_m;
}

TEST(RouteExecutorTest, APlannedPathToldBeforeTheActionIsDrivenThrough) {
  FreeNavigationAction nav;
  nav.goal = Pose2(12.0, 3.0, 0.0);
  RouteExecutor executor(MakeRoute({Act(nav, {EndConditionKind::kGoalReached, 0})}), OmniInRoom());
  executor.SetClearedUpTo(-1);
  executor.SetActionPath(ActionPath{0, 7, {{7.0, 5.0}}});
  ASSERT_EQ(std::get<FreeNavigationAction>(executor.route().actions[0].params).waypoints_m.size(),
            1u);
  executor.SetClearedUpTo(0);
  const std::vector<Pose2> driven =
      DriveOmni(executor, Pose2(2.0, 3.0, 0.0), [](double, const Pose2&) {});
  EXPECT_EQ(executor.state(), ExecutionState::kSucceeded) << executor.failure();
  EXPECT_LT(ClosestM(driven, {7.0, 5.0}), 0.3);
  EXPECT_LT((driven.back().translation() - nav.goal.translation()).norm(), 0.1);
}

TEST(RouteExecutorTest, APlannedPathToldUnderWayIsDrivenFromWhereTheRobotIs) {
  FreeNavigationAction nav;
  nav.goal = Pose2(12.0, 3.0, 0.0);
  RouteExecutor executor(MakeRoute({Act(nav, {EndConditionKind::kGoalReached, 0})}), OmniInRoom());
  bool told = false;
  double progress_when_told = 0.0;
  double least_progress_after = 1.0;
  const std::vector<Pose2> driven =
      DriveOmni(executor, Pose2(2.0, 3.0, 0.0), [&](double progress, const Pose2& pose) {
        if (told) least_progress_after = std::min(least_progress_after, progress);
        if (!told && pose.x_m() > 5.0) {
          executor.SetActionPath(ActionPath{0, 9, {{8.0, 1.2}}});
          told = true;
          progress_when_told = progress;
        }
      });
  ASSERT_TRUE(told);
  // Its progress goes on from what was done (the new way's own counts the rest).
  EXPECT_GT(progress_when_told, 0.2);
  EXPECT_GE(least_progress_after, progress_when_told - 1e-9);
  EXPECT_EQ(executor.state(), ExecutionState::kSucceeded) << executor.failure();
  EXPECT_LT(ClosestM(driven, {8.0, 1.2}), 0.3);
  // Driven on the map alone the way stays on y = 3.
  RouteExecutor alone(MakeRoute({Act(nav, {EndConditionKind::kGoalReached, 0})}), OmniInRoom());
  EXPECT_GT(
      ClosestM(DriveOmni(alone, Pose2(2.0, 3.0, 0.0), [](double, const Pose2&) {}), {8.0, 1.2}),
      1.0);
}

TEST(RouteExecutorTest, AWayThatTurnsBackJustBeforeItsGateIsHeldThereInPathOrder) {
  // Out east to a place beside the way (where it steps aside), then back west: the gate where
  // its cleared segment ends lies just beyond the place, so the robot turns back before the
  // gate's line. Held by path order it stands at the place; a hold by heading would let it
  // drive back west past whoever it stepped aside for.
  FreeNavigationAction nav;
  nav.goal = Pose2(3.0, 4.0, kPi);
  RouteExecutor executor(MakeRoute({Act(nav, {EndConditionKind::kGoalReached, 0})}), OmniInRoom());
  executor.SetActionPath(ActionPath{0, 1, {{9.0, 3.0}}});
  executor.SetClearedUpTo(0);
  const Pose2 gate(9.2, 3.0, 0.0);
  executor.SetHold(SegmentHold{0, 0, gate});
  std::vector<Pose2> driven = {Pose2(2.0, 3.0, 0.0)};
  ExecutorOutput out;
  for (int i = 0; i < 3000; ++i) {  // 60 s: long enough to have driven the whole way back
    out = executor.Step(OdometryInput(driven.back(), kDt));
    driven.push_back(testing::MovedOmni(driven.back(), out.command, kDt));
  }
  EXPECT_EQ(out.state, ExecutionState::kRunning) << executor.failure();
  EXPECT_EQ(out.mode, NavigationMode::kIdle);
  EXPECT_LT((driven.back().translation() - Eigen::Vector2d(9.0, 3.0)).norm(), 0.3);
  EXPECT_TRUE(ReachedGate(gate, driven.back().translation()));  // the server sees it there
  // Cleared on, it drives back to the goal.
  executor.SetHold(std::nullopt);
  driven = DriveOmni(executor, driven.back(), [](double, const Pose2&) {});
  EXPECT_EQ(executor.state(), ExecutionState::kSucceeded) << executor.failure();
  EXPECT_LT((driven.back().translation() - nav.goal.translation()).norm(), 0.1);
}

TEST(RouteExecutorTest, APlannedPathForAnotherKindOfActionOrTakenBeforeIsIgnored) {
  FreeNavigationAction nav;
  nav.goal = Pose2(12.0, 3.0, 0.0);
  RouteExecutor executor(
      MakeRoute({Act(StraightAction{1.0, 0.3}), Act(nav, {EndConditionKind::kGoalReached, 0})}),
      OmniInRoom());
  executor.SetActionPath(ActionPath{0, 1, {{7.0, 5.0}}});  // a straight: nothing to plan
  EXPECT_TRUE(std::holds_alternative<StraightAction>(executor.route().actions[0].params));
  executor.SetActionPath(ActionPath{1, 2, {{7.0, 5.0}}});
  executor.SetActionPath(ActionPath{1, 2, {{7.0, 1.0}}});  // the same plan told again
  const auto waypoints = [&] {
    return std::get<FreeNavigationAction>(executor.route().actions[1].params).waypoints_m;
  };
  ASSERT_EQ(waypoints().size(), 1u);
  EXPECT_DOUBLE_EQ(waypoints()[0].y(), 5.0);
  executor.SetActionPath(ActionPath{1, 3, {{7.0, 1.0}}});  // a new plan
  EXPECT_DOUBLE_EQ(waypoints()[0].y(), 1.0);
  executor.SetActionPath(ActionPath{5, 4, {{7.0, 1.0}}});  // no such action
  EXPECT_EQ(executor.route().actions.size(), 2u);
}

}  // namespace
}  // namespace fleetnav::agent
