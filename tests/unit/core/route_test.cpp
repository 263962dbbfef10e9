#include "fleetnav/core/route.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/stripe_marker.hpp"

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

void ExpectInvalid(const absl::Status& status, const std::string& needle) {
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument) << status;
  EXPECT_THAT(std::string(status.message()), HasSubstr(needle));
}

RouteAction Act(ActionParams params, EndCondition end = {}) { return RouteAction{params, end}; }

// The feed round of the Lely thesis §1.1.3 in route form.
Route FeedRound() {
  Route route;
  route.name = "feed-round-1";
  route.map_id = "barn";
  route.actions = {
      Act(StraightAction{5.0, 0.25}),
      Act(TurnAction{kPi / 2.0, 0.3}),
      Act(StraightAction{3.0, 0.25}, {EndConditionKind::kMarkerDetected, 4}),
      Act(FreeNavigationAction{{{1, 2}, {3, 4}}, Pose2(5, 6, kPi / 2), 0.25},
          {EndConditionKind::kGoalReached, 0}),
      Act(FenceNavigationAction{Side::kLeft, 0.5, 10.0, 0.25}),
      Act(StripeNavigationAction{3, 12.0, 0.25}, {EndConditionKind::kStripeEnd, 0}),
      Act(DockAction{DockTarget::kCharger, "pole-1"}, {EndConditionKind::kChargerContact, 0}),
  };
  return route;
}

TEST(RouteValidateTest, AcceptsAValidRoute) { EXPECT_TRUE(FeedRound().Validate().ok()); }

TEST(RouteValidateTest, NeedsNameAndActions) {
  Route unnamed = FeedRound();
  unnamed.name.clear();
  ExpectInvalid(unnamed.Validate(), "name must not be empty");
  Route empty = FeedRound();
  empty.actions.clear();
  ExpectInvalid(empty.Validate(), "actions must not be empty");
}

TEST(RouteValidateTest, StraightDistanceAndSpeed) {
  Route route = FeedRound();
  route.actions[2] = Act(StraightAction{0.0, 0.25});
  ExpectInvalid(route.Validate(), "actions[2] (straight): distance_m must be > 0");
  route.actions[2] = Act(StraightAction{-1.0, 0.25}, {EndConditionKind::kMarkerDetected, 1});
  ExpectInvalid(route.Validate(), "actions[2] (straight): distance_m must be > 0, got -1");
  route.actions[2] = Act(StraightAction{1.0, std::nan("")});
  ExpectInvalid(route.Validate(), "actions[2] (straight): speed_mps must be > 0, got nan");
  route.actions[2] = Act(StraightAction{1.0, 0.2}, {EndConditionKind::kStripeEnd, 0});
  ExpectInvalid(route.Validate(), "actions[2] (straight): end condition 'stripe_end'");
}

TEST(RouteValidateTest, TurnAngleAndRate) {
  Route route = FeedRound();
  route.actions[1] = Act(TurnAction{0.0, 0.3});
  ExpectInvalid(route.Validate(), "actions[1] (turn): angle_rad must be finite, non-zero");
  route.actions[1] = Act(TurnAction{7.0, 0.3});
  ExpectInvalid(route.Validate(), "actions[1] (turn): angle_rad");
  route.actions[1] = Act(TurnAction{-2.0 * kPi, 0.3});
  EXPECT_TRUE(route.Validate().ok());
  route.actions[1] = Act(TurnAction{1.0, 0.0});
  ExpectInvalid(route.Validate(), "actions[1] (turn): yaw_rate_radps must be > 0");
  route.actions[1] = Act(TurnAction{1.0, 0.3}, {EndConditionKind::kMarkerDetected, 2});
  EXPECT_TRUE(route.Validate().ok());
}

TEST(RouteValidateTest, FreeNavigationGoalMustBeFinite) {
  Route route = FeedRound();
  route.actions[3] = Act(FreeNavigationAction{{}, Pose2(std::nan(""), 0, 0), 0.25});
  ExpectInvalid(route.Validate(), "actions[3] (free_navigation): goal must be finite");
  route.actions[3] = Act(FreeNavigationAction{{{0, std::nan("")}}, Pose2(), 0.25});
  ExpectInvalid(route.Validate(), "actions[3] (free_navigation): waypoints_m[0] must be finite");
  route.actions[3] = Act(FreeNavigationAction{{}, Pose2(), 0.25});  // default end
  EXPECT_TRUE(route.Validate().ok());
  route.actions[3] = Act(FreeNavigationAction{{}, Pose2(), 0.25}, {EndConditionKind::kStripeEnd});
  ExpectInvalid(route.Validate(), "actions[3] (free_navigation): end condition 'stripe_end'");
}

TEST(RouteValidateTest, FenceDistanceZeroOnlyWithSensorEnd) {
  Route route = FeedRound();
  route.actions[4] = Act(FenceNavigationAction{Side::kRight, 0.5, 0.0, 0.25});
  ExpectInvalid(route.Validate(),
                "actions[4] (fence_navigation): distance_m must be > 0 unless the action ends on "
                "a marker or stripe_end");
  route.actions[4] = Act(FenceNavigationAction{Side::kRight, 0.5, 0.0, 0.25},
                         {EndConditionKind::kMarkerDetected, 2});
  EXPECT_TRUE(route.Validate().ok());
  route.actions[4] = Act(FenceNavigationAction{Side::kRight, 0.0, 5.0, 0.25});
  ExpectInvalid(route.Validate(), "actions[4] (fence_navigation): fence_distance_m must be > 0");
  route.actions[4] = Act(FenceNavigationAction{Side::kRight, 0.5, -1.0, 0.25},
                         {EndConditionKind::kMarkerDetected, 2});
  ExpectInvalid(route.Validate(), "distance_m must be finite and >= 0, got -1");
}

TEST(RouteValidateTest, StripeDistanceZeroOnlyWithSensorEnd) {
  Route route = FeedRound();
  route.actions[5] = Act(StripeNavigationAction{3, 0.0, 0.25});
  ExpectInvalid(route.Validate(), "actions[5] (stripe_navigation): distance_m must be > 0");
  route.actions[5] = Act(StripeNavigationAction{3, 0.0, 0.25}, {EndConditionKind::kStripeEnd});
  EXPECT_TRUE(route.Validate().ok());
  route.actions[5] = Act(StripeNavigationAction{-1, 5.0, 0.25});
  ExpectInvalid(route.Validate(), "actions[5] (stripe_navigation): stripe_id must be >= 0");
}

TEST(RouteValidateTest, DockEndConditions) {
  Route route = FeedRound();
  route.actions[6] = Act(DockAction{DockTarget::kCharger, ""});  // default end condition
  EXPECT_TRUE(route.Validate().ok());
  route.actions[6] = Act(DockAction{DockTarget::kCharger, ""}, {EndConditionKind::kGoalReached, 0});
  ExpectInvalid(route.Validate(),
                "actions[6] (dock): end condition 'goal_reached' does not fit this action "
                "(allowed: charger_contact, distance)");
  route.actions[6] =
      Act(DockAction{DockTarget::kTrolley, "t1"}, {EndConditionKind::kGoalReached, 0});
  EXPECT_TRUE(route.Validate().ok());
}

TEST(CarriedLoadTest, ATrolleyDockLoadsTheLiftAndAnUndockEmptiesIt) {
  MarkerSet markers;
  TrolleyPlacement trolley;
  trolley.id = "t1";
  trolley.size_m = Eigen::Vector2d(1.2, 0.8);
  markers.trolleys.push_back(trolley);
  const Eigen::Vector2d unknown_m(0.9, 0.6);
  const std::optional<Eigen::Vector2d> none;

  const auto docked =
      CarriedLoadAfter(Act(DockAction{DockTarget::kTrolley, "t1"}), none, &markers, unknown_m);
  ASSERT_TRUE(docked.has_value());
  EXPECT_EQ(*docked, trolley.size_m);
  // A trolley the marker set does not hold, or no marker set: the caller's size.
  EXPECT_EQ(
      *CarriedLoadAfter(Act(DockAction{DockTarget::kTrolley, "t9"}), none, &markers, unknown_m),
      unknown_m);
  EXPECT_EQ(
      *CarriedLoadAfter(Act(DockAction{DockTarget::kTrolley, "t1"}), none, nullptr, unknown_m),
      unknown_m);
  // Driving keeps the load; a charger dock does not load; an undock sets it down.
  EXPECT_EQ(*CarriedLoadAfter(Act(StraightAction{1.0, 0.3}), docked, &markers, unknown_m),
            trolley.size_m);
  EXPECT_FALSE(
      CarriedLoadAfter(Act(DockAction{DockTarget::kCharger, ""}), none, &markers, unknown_m)
          .has_value());
  EXPECT_FALSE(CarriedLoadAfter(Act(UndockAction{}), docked, &markers, unknown_m).has_value());
}

TEST(RouteNamesTest, ActionAndEndConditionNames) {
  EXPECT_EQ(ActionTypeName(TurnAction{}), "turn");
  EXPECT_EQ(ActionTypeName(StraightAction{}), "straight");
  EXPECT_EQ(ActionTypeName(FreeNavigationAction{}), "free_navigation");
  EXPECT_EQ(ActionTypeName(FenceNavigationAction{}), "fence_navigation");
  EXPECT_EQ(ActionTypeName(StripeNavigationAction{}), "stripe_navigation");
  EXPECT_EQ(ActionTypeName(DockAction{}), "dock");
  for (EndConditionKind kind : {EndConditionKind::kDistance, EndConditionKind::kMarkerDetected,
                                EndConditionKind::kStripeEnd, EndConditionKind::kChargerContact,
                                EndConditionKind::kGoalReached}) {
    absl::StatusOr<EndConditionKind> parsed = ParseEndConditionKind(EndConditionKindName(kind));
    ASSERT_TRUE(parsed.ok());
    EXPECT_EQ(*parsed, kind);
  }
  ExpectInvalid(ParseEndConditionKind("teleport").status(), "unknown end condition 'teleport'");
}

}  // namespace
}  // namespace fleetnav
