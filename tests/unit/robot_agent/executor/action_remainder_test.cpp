#include "fleetnav/robot_agent/action_remainder.hpp"

#include <gtest/gtest.h>

#include "fleetnav/core/angles.hpp"

namespace fleetnav::agent {
namespace {

TEST(ActionRemainderTest, StraightAndTurnKeepWhatIsLeft) {
  std::optional<RouteAction> straight =
      RemainderOf({StraightAction{4.0, 0.3}, {}}, 0.25, Pose2(1, 0, 0));
  ASSERT_TRUE(straight.has_value());
  EXPECT_DOUBLE_EQ(std::get<StraightAction>(straight->params).distance_m, 3.0);
  EXPECT_DOUBLE_EQ(std::get<StraightAction>(straight->params).speed_mps, 0.3);

  std::optional<RouteAction> turn = RemainderOf({TurnAction{DegToRad(-90), 0.3}, {}}, 0.5, Pose2());
  ASSERT_TRUE(turn.has_value());
  EXPECT_NEAR(std::get<TurnAction>(turn->params).angle_rad, DegToRad(-45), 1e-12);

  EXPECT_FALSE(RemainderOf({StraightAction{4.0, 0.3}, {}}, 0.999, Pose2()).has_value());
  EXPECT_FALSE(RemainderOf({TurnAction{DegToRad(90), 0.3}, {}}, 1.0, Pose2()).has_value());
}

TEST(ActionRemainderTest, LegsEndingOnAMarkerKeepSlackBeyondTheirRemainder) {
  FenceNavigationAction fence;
  fence.distance_m = 10.0;
  std::optional<RouteAction> by_distance = RemainderOf({fence, {}}, 0.4, Pose2());
  ASSERT_TRUE(by_distance.has_value());
  EXPECT_DOUBLE_EQ(std::get<FenceNavigationAction>(by_distance->params).distance_m, 6.0);

  std::optional<RouteAction> to_marker =
      RemainderOf({fence, {EndConditionKind::kMarkerDetected, 4}}, 0.4, Pose2());
  ASSERT_TRUE(to_marker.has_value());
  EXPECT_DOUBLE_EQ(std::get<FenceNavigationAction>(to_marker->params).distance_m, 6.0 + kEndSlackM);
  EXPECT_EQ(to_marker->end.marker_id, 4);
  // Even "all done" by distance: the marker is still searched for a little.
  ASSERT_TRUE(RemainderOf({fence, {EndConditionKind::kMarkerDetected, 4}}, 1.0, Pose2()));

  StripeNavigationAction stripe;
  stripe.stripe_id = 3;
  stripe.distance_m = 0.0;  // unbounded: nothing to scale
  std::optional<RouteAction> unbounded =
      RemainderOf({stripe, {EndConditionKind::kStripeEnd}}, 0.7, Pose2());
  ASSERT_TRUE(unbounded.has_value());
  EXPECT_DOUBLE_EQ(std::get<StripeNavigationAction>(unbounded->params).distance_m, 0.0);
}

TEST(ActionRemainderTest, FreeNavigationDropsTheWaypointsBehindTheRobot) {
  FreeNavigationAction nav;
  nav.waypoints_m = {{2, 0}, {4, 0}, {4, 3}};
  nav.goal = Pose2(0, 3, kPi);
  const auto ahead = [&](const Pose2& at) {
    return std::get<FreeNavigationAction>(RemainderOf({nav, {}}, 0.5, at)->params).waypoints_m;
  };
  EXPECT_EQ(ahead(Pose2(0, 0, 0)).size(), 3u);    // before the first waypoint
  EXPECT_EQ(ahead(Pose2(3, 0.1, 0)).size(), 2u);  // between the first two
  EXPECT_EQ(ahead(Pose2(4.1, 1.5, 0)).size(), 1u);
  EXPECT_EQ(ahead(Pose2(2, 3.1, 0)).size(), 0u);  // on the way to the goal
  EXPECT_EQ(std::get<FreeNavigationAction>(RemainderOf({nav, {}}, 0.5, Pose2())->params).goal.x_m(),
            0.0);
}

TEST(ActionRemainderTest, DockIsKeptAsItIs) {
  std::optional<RouteAction> dock =
      RemainderOf({DockAction{}, {EndConditionKind::kChargerContact}}, 0.5, Pose2());
  ASSERT_TRUE(dock.has_value());
  EXPECT_TRUE(std::holds_alternative<DockAction>(dock->params));
}

}  // namespace
}  // namespace fleetnav::agent
