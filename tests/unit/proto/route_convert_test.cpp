#include "fleetnav/proto/route_convert.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>

#include "fleetnav/core/angles.hpp"

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

template <typename T>
void ExpectInvalid(const absl::StatusOr<T>& result, const std::string& field) {
  ASSERT_FALSE(result.ok()) << "expected InvalidArgument naming '" << field << "'";
  EXPECT_EQ(result.status().code(), absl::StatusCode::kInvalidArgument) << result.status();
  EXPECT_THAT(std::string(result.status().message()), HasSubstr(field));
}

RouteAction Act(ActionParams params, EndCondition end = {}) { return RouteAction{params, end}; }

// Every action type at least once, with every end condition kind.
Route EveryActionRoute() {
  Route route;
  route.name = "feed-round-1";
  route.map_id = "barn";
  route.actions = {
      Act(StraightAction{5.0, 0.25}),
      Act(TurnAction{kPi / 2.0, 0.3}, {EndConditionKind::kMarkerDetected, 11}),
      Act(FreeNavigationAction{{{1.0, 2.0}, {3.5, -4.25}}, Pose2(5.0, 6.0, -kPi / 3.0), 0.4},
          {EndConditionKind::kGoalReached, 0}),
      Act(FenceNavigationAction{Side::kRight, 0.6, 12.5, 0.2}),
      Act(FenceNavigationAction{Side::kLeft, 0.5, 0.0, 0.25}, {EndConditionKind::kStripeEnd, 0}),
      Act(StripeNavigationAction{3, 0.0, 0.15}, {EndConditionKind::kMarkerDetected, 4}),
      Act(DockAction{DockTarget::kCharger, "pole-1"}, {EndConditionKind::kChargerContact, 0}),
      Act(DockAction{DockTarget::kTrolley, "trolley-7"}, {EndConditionKind::kGoalReached, 0}),
      Act(UndockAction{}),
  };
  return route;
}

void ExpectSameAction(const RouteAction& actual, const RouteAction& expected) {
  ASSERT_EQ(actual.params.index(), expected.params.index());
  EXPECT_EQ(actual.end.kind, expected.end.kind);
  EXPECT_EQ(actual.end.marker_id, expected.end.marker_id);
  if (const auto* e = std::get_if<TurnAction>(&expected.params)) {
    const auto& a = std::get<TurnAction>(actual.params);
    EXPECT_EQ(a.angle_rad, e->angle_rad);
    EXPECT_EQ(a.yaw_rate_radps, e->yaw_rate_radps);
  } else if (const auto* e = std::get_if<StraightAction>(&expected.params)) {
    const auto& a = std::get<StraightAction>(actual.params);
    EXPECT_EQ(a.distance_m, e->distance_m);
    EXPECT_EQ(a.speed_mps, e->speed_mps);
  } else if (const auto* e = std::get_if<FreeNavigationAction>(&expected.params)) {
    const auto& a = std::get<FreeNavigationAction>(actual.params);
    EXPECT_EQ(a.waypoints_m, e->waypoints_m);
    EXPECT_TRUE(a.goal.IsNear(e->goal, 0.0, 0.0)) << a.goal.DebugString();
    EXPECT_EQ(a.speed_mps, e->speed_mps);
  } else if (const auto* e = std::get_if<FenceNavigationAction>(&expected.params)) {
    const auto& a = std::get<FenceNavigationAction>(actual.params);
    EXPECT_EQ(a.side, e->side);
    EXPECT_EQ(a.fence_distance_m, e->fence_distance_m);
    EXPECT_EQ(a.distance_m, e->distance_m);
    EXPECT_EQ(a.speed_mps, e->speed_mps);
  } else if (const auto* e = std::get_if<StripeNavigationAction>(&expected.params)) {
    const auto& a = std::get<StripeNavigationAction>(actual.params);
    EXPECT_EQ(a.stripe_id, e->stripe_id);
    EXPECT_EQ(a.distance_m, e->distance_m);
    EXPECT_EQ(a.speed_mps, e->speed_mps);
  } else if (std::holds_alternative<UndockAction>(expected.params)) {
    // no parameters: the variant's index above says it all
  } else {
    const auto& e_dock = std::get<DockAction>(expected.params);
    const auto& a = std::get<DockAction>(actual.params);
    EXPECT_EQ(a.target, e_dock.target);
    EXPECT_EQ(a.target_id, e_dock.target_id);
  }
}

TEST(RouteConvertTest, EveryActionTypeRoundTrips) {
  const Route route = EveryActionRoute();
  ASSERT_TRUE(route.Validate().ok()) << route.Validate();
  const v1::Route wire = ToProto(route);
  EXPECT_EQ(wire.name(), "feed-round-1");
  EXPECT_EQ(wire.map_id(), "barn");
  ASSERT_EQ(wire.actions_size(), 9);
  EXPECT_EQ(wire.actions(8).action_case(), v1::RouteAction::kUndock);
  EXPECT_EQ(wire.actions(0).action_case(), v1::RouteAction::kStraight);
  EXPECT_EQ(wire.actions(1).action_case(), v1::RouteAction::kTurn);
  EXPECT_EQ(wire.actions(2).action_case(), v1::RouteAction::kFreeNavigation);
  EXPECT_EQ(wire.actions(3).action_case(), v1::RouteAction::kFenceNavigation);
  EXPECT_EQ(wire.actions(3).fence_navigation().side(), v1::SIDE_RIGHT);
  EXPECT_EQ(wire.actions(5).action_case(), v1::RouteAction::kStripeNavigation);
  EXPECT_EQ(wire.actions(6).action_case(), v1::RouteAction::kDock);
  EXPECT_EQ(wire.actions(6).dock().target(), v1::DOCK_TARGET_CHARGER);
  EXPECT_EQ(wire.actions(7).dock().target(), v1::DOCK_TARGET_TROLLEY);
  EXPECT_EQ(wire.actions(1).end().kind(), v1::END_CONDITION_KIND_MARKER_DETECTED);
  EXPECT_EQ(wire.actions(1).end().marker_id(), 11);
  EXPECT_EQ(wire.actions(4).end().kind(), v1::END_CONDITION_KIND_STRIPE_END);
  EXPECT_EQ(wire.actions(6).end().kind(), v1::END_CONDITION_KIND_CHARGER_CONTACT);

  const absl::StatusOr<Route> back = FromProto(wire);
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_EQ(back->name, route.name);
  EXPECT_EQ(back->map_id, route.map_id);
  ASSERT_EQ(back->actions.size(), route.actions.size());
  for (size_t i = 0; i < route.actions.size(); ++i) {
    SCOPED_TRACE(::testing::Message() << "actions[" << i << "]");
    ExpectSameAction(back->actions[i], route.actions[i]);
  }
}

TEST(RouteConvertTest, UnspecifiedEndKindGetsTheActionsDefault) {
  v1::Route wire = ToProto(EveryActionRoute());
  for (v1::RouteAction& action : *wire.mutable_actions()) {
    if (action.end().kind() != v1::END_CONDITION_KIND_MARKER_DETECTED &&
        action.end().kind() != v1::END_CONDITION_KIND_STRIPE_END) {
      action.mutable_end()->set_kind(v1::END_CONDITION_KIND_UNSPECIFIED);
    }
  }
  // Index 3 is a fence run with a distance, so its default (distance) is valid.
  const absl::StatusOr<Route> back = FromProto(wire);
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_EQ(back->actions[0].end.kind, EndConditionKind::kDistance);        // straight
  EXPECT_EQ(back->actions[2].end.kind, EndConditionKind::kGoalReached);     // free navigation
  EXPECT_EQ(back->actions[3].end.kind, EndConditionKind::kDistance);        // fence
  EXPECT_EQ(back->actions[6].end.kind, EndConditionKind::kChargerContact);  // dock at charger
  EXPECT_EQ(back->actions[7].end.kind, EndConditionKind::kGoalReached);     // dock at trolley
}

TEST(RouteConvertTest, UnspecifiedEndKindOfTurnIsDistance) {
  v1::Route wire;
  wire.set_name("turn");
  wire.mutable_actions()->Add()->mutable_turn()->set_angle_rad(1.0);
  wire.mutable_actions(0)->mutable_turn()->set_yaw_rate_radps(0.3);
  const absl::StatusOr<Route> back = FromProto(wire);
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_EQ(back->actions[0].end.kind, EndConditionKind::kDistance);
}

TEST(RouteConvertTest, RefusesActionWithNoTypeNamingItsIndex) {
  v1::Route wire = ToProto(EveryActionRoute());
  wire.mutable_actions(1)->clear_action();
  const absl::StatusOr<Route> result = FromProto(wire);
  ExpectInvalid(result, "actions[1]");
  EXPECT_THAT(std::string(result.status().message()), HasSubstr("no action type"));
}

TEST(RouteConvertTest, RefusesUnknownEndKind) {
  v1::Route wire = ToProto(EveryActionRoute());
  wire.mutable_actions(2)->mutable_end()->set_kind(static_cast<v1::EndConditionKind>(99));
  ExpectInvalid(FromProto(wire), "actions[2].end.kind");
  wire.mutable_actions(2)->mutable_end()->set_kind(static_cast<v1::EndConditionKind>(-1));
  ExpectInvalid(FromProto(wire), "actions[2].end.kind");
}

TEST(RouteConvertTest, RefusesUnspecifiedOrUnknownSideAndDockTarget) {
  v1::Route wire = ToProto(EveryActionRoute());
  wire.mutable_actions(3)->mutable_fence_navigation()->set_side(v1::SIDE_UNSPECIFIED);
  ExpectInvalid(FromProto(wire), "actions[3].fence_navigation.side");
  wire = ToProto(EveryActionRoute());
  wire.mutable_actions(4)->mutable_fence_navigation()->set_side(static_cast<v1::Side>(99));
  ExpectInvalid(FromProto(wire), "actions[4].fence_navigation.side");
  wire = ToProto(EveryActionRoute());
  wire.mutable_actions(6)->mutable_dock()->set_target(v1::DOCK_TARGET_UNSPECIFIED);
  ExpectInvalid(FromProto(wire), "actions[6].dock.target");
  wire = ToProto(EveryActionRoute());
  wire.mutable_actions(7)->mutable_dock()->set_target(static_cast<v1::DockTarget>(99));
  ExpectInvalid(FromProto(wire), "actions[7].dock.target");
}

TEST(RouteConvertTest, RefusesNonFiniteNumbersNamingTheAction) {
  v1::Route wire = ToProto(EveryActionRoute());
  wire.mutable_actions(2)->mutable_free_navigation()->mutable_waypoints(1)->set_x_m(kNan);
  ExpectInvalid(FromProto(wire), "actions[2].waypoints[1]");
  wire = ToProto(EveryActionRoute());
  wire.mutable_actions(2)->mutable_free_navigation()->mutable_goal()->set_yaw_rad(kNan);
  ExpectInvalid(FromProto(wire), "actions[2].goal");
  wire = ToProto(EveryActionRoute());
  wire.mutable_actions(0)->mutable_straight()->set_distance_m(kNan);
  ExpectInvalid(FromProto(wire), "actions[0] (straight): distance_m");
  wire = ToProto(EveryActionRoute());
  wire.mutable_actions(1)->mutable_turn()->set_angle_rad(kNan);
  ExpectInvalid(FromProto(wire), "actions[1] (turn): angle_rad");
}

TEST(RouteConvertTest, RunsRouteValidation) {
  v1::Route wire = ToProto(EveryActionRoute());
  wire.set_name("");
  ExpectInvalid(FromProto(wire), "name");
  wire = ToProto(EveryActionRoute());
  wire.clear_actions();
  ExpectInvalid(FromProto(wire), "actions must not be empty");
  wire = ToProto(EveryActionRoute());
  // A straight run may not end at the charger contact.
  wire.mutable_actions(0)->mutable_end()->set_kind(v1::END_CONDITION_KIND_CHARGER_CONTACT);
  ExpectInvalid(FromProto(wire), "actions[0] (straight): end condition");
}

}  // namespace
}  // namespace fleetnav
