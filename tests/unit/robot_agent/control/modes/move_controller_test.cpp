// The move action (KUKA thesis ch. 9): validation and refusal for kinds that cannot translate
// sideways, the straight path, the augmented path that bends round a reversal, and the
// platform brought to its end point (ideal omnidirectional kinematics).
#include "fleetnav/robot_agent/control/modes/move_controller.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/robot_agent/mode_factory.hpp"
#include "kinematic_unicycle.hpp"

namespace fleetnav::agent {
namespace {

/// Steps `controller` on an ideal omnidirectional body from `start` until done; returns the end
/// and, in `max_y_m`, the largest y the body reached.
Pose2 RunIdeal(MoveController& controller, Pose2 pose, int* ticks, double* max_y_m = nullptr) {
  constexpr double kDtS = 0.02;
  for (*ticks = 0; *ticks < 5000; ++*ticks) {
    ControlInput input;
    input.pose_in_map = pose;
    input.pose_in_odom = pose;
    input.dt_s = kDtS;
    const ControlOutput out = controller.Step(input);
    EXPECT_TRUE(out.failure.ok()) << out.failure;
    if (out.done) break;
    pose = testing::MovedOmni(pose, out.command, kDtS);
    if (max_y_m != nullptr) *max_y_m = std::max(*max_y_m, pose.y_m());
  }
  return pose;
}

double MaxAlong(const std::vector<Pose2>& path, const Eigen::Vector2d& axis) {
  double best = -1e9;
  for (const Pose2& p : path) best = std::max(best, p.translation().dot(axis));
  return best;
}

TEST(MoveControllerTest, MovesSidewaysWithItsHeadingHeld) {
  const RobotModel model = MecanumPlatformModel();
  MoveController controller(MoveAction{0.0, 1.0, 0.2}, std::nullopt, model, MoveParams{});
  int ticks = 0;
  const Pose2 start(2.0, 1.0, (kPi / 2));  // facing +y: its left is -x
  const Pose2 end = RunIdeal(controller, start, &ticks);
  EXPECT_LT(ticks, 5000);
  EXPECT_NEAR(end.x_m(), 1.0, 0.002);
  EXPECT_NEAR(end.y_m(), 1.0, 0.002);
  EXPECT_NEAR(end.yaw_rad(), (kPi / 2), 0.01);
  // The path is the straight line: it never leaves x in [1, 2] nor y = 1.
  for (const Pose2& p : controller.path()) EXPECT_NEAR(p.y_m(), 1.0, 1e-9);
}

TEST(MoveControllerTest, AReversalBendsRoundThroughTheAugmentedKnot) {
  const RobotModel model = MecanumPlatformModel();
  const Eigen::Vector2d came_left(0.0, 1.0);  // the last move went to the left
  MoveController augmented(MoveAction{0.0, -1.0, 0.2}, came_left, model, MoveParams{});
  int ticks = 0;
  double max_y_m = 0.0;
  const Pose2 end = RunIdeal(augmented, Pose2(0, 0, 0), &ticks, &max_y_m);
  EXPECT_NEAR(end.y_m(), -1.0, 0.002);
  // The platform itself follows the bend (the tracker does not cut across it).
  EXPECT_GT(max_y_m, 0.03);
  EXPECT_NEAR(end.x_m(), 0.0, 0.002);
  // It first carries on to the left (the casters keep rolling) and swings out sideways.
  const std::vector<Pose2>& path = augmented.path();
  ASSERT_GT(path.size(), 10u);
  EXPECT_GT(path[1].y_m(), path[0].y_m());
  EXPECT_GT(MaxAlong(path, {0, 1}), 0.05);
  EXPECT_GT(std::abs(MaxAlong(path, {1, 0})) + std::abs(MaxAlong(path, {-1, 0})), 0.05);

  MoveParams plain_params;
  plain_params.augment_endpoints = false;
  MoveController plain(MoveAction{0.0, -1.0, 0.2}, came_left, model, plain_params);
  double plain_max_y_m = 0.0;
  (void)RunIdeal(plain, Pose2(0, 0, 0), &ticks, &plain_max_y_m);
  EXPECT_LT(MaxAlong(plain.path(), {0, 1}), 1e-9);  // straight back
  EXPECT_LT(plain_max_y_m, 0.005);
  // A move that continues the last direction needs no augmentation either.
  MoveController onwards(MoveAction{0.0, 1.0, 0.2}, came_left, model, MoveParams{});
  (void)RunIdeal(onwards, Pose2(0, 0, 0), &ticks);
  for (const Pose2& p : onwards.path()) EXPECT_NEAR(p.x_m(), 0.0, 1e-9);
}

TEST(MoveActionTest, ValidatedAndRefusedForKindsThatCannotTranslateSideways) {
  Route route{"r", "m", {RouteAction{MoveAction{0.0, 0.0, 0.2}, {}}}};
  absl::Status bad = route.Validate();
  EXPECT_EQ(bad.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(bad.message().find("actions[0] (move)"), std::string::npos) << bad;
  route.actions[0].params = MoveAction{0.0, 1.0, -0.1};
  EXPECT_EQ(route.Validate().code(), absl::StatusCode::kInvalidArgument);
  route.actions[0].params = MoveAction{0.0, 1.0, 0.2};
  ASSERT_TRUE(route.Validate().ok());

  const RouteContext lely{LelyVectorModel(), std::nullopt, nullptr};
  const absl::Status refused = CheckRoute(route, lely);
  EXPECT_EQ(refused.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_NE(refused.message().find("lely-vector cannot translate sideways"), std::string::npos)
      << refused;
  const RouteContext car{AckermannDeliveryModel(), std::nullopt, nullptr};
  EXPECT_EQ(CheckRoute(route, car).code(), absl::StatusCode::kFailedPrecondition);
  const RouteContext omni{MecanumPlatformModel(), std::nullopt, nullptr};
  EXPECT_TRUE(CheckRoute(route, omni).ok());
  const std::vector<std::string> types = SupportedActionTypes(MecanumPlatformModel());
  EXPECT_NE(std::find(types.begin(), types.end(), "move"), types.end());
  const std::vector<std::string> lely_types = SupportedActionTypes(LelyVectorModel());
  EXPECT_EQ(std::find(lely_types.begin(), lely_types.end(), "move"), lely_types.end());

  // The route file: parsed, written and read back.
  absl::StatusOr<Route> parsed =
      ParseRouteYaml("name: r\nmap: m\nactions:\n  - move: {dx: -0.5, dy: 1.0, speed: 0.3}\n");
  ASSERT_TRUE(parsed.ok()) << parsed.status();
  const auto& move = std::get<MoveAction>(parsed->actions[0].params);
  EXPECT_DOUBLE_EQ(move.dx_m, -0.5);
  EXPECT_DOUBLE_EQ(move.dy_m, 1.0);
  EXPECT_DOUBLE_EQ(move.speed_mps, 0.3);
  absl::StatusOr<Route> back = ParseRouteYaml(RouteToYaml(*parsed));
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_DOUBLE_EQ(std::get<MoveAction>(back->actions[0].params).dx_m, -0.5);
  EXPECT_EQ(ParseRouteYaml("name: r\nmap: m\nactions:\n  - move: {dz: 1}\n").status().code(),
            absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fleetnav::agent
