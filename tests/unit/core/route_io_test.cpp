#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/route.hpp"

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

void ExpectInvalid(const absl::StatusOr<Route>& result, const std::string& needle) {
  ASSERT_FALSE(result.ok()) << "expected an error containing '" << needle << "'";
  EXPECT_EQ(result.status().code(), absl::StatusCode::kInvalidArgument) << result.status();
  EXPECT_THAT(std::string(result.status().message()), HasSubstr(needle));
}

// The example from route.hpp.
constexpr char kExample[] = R"(name: feed-round-1
map: barn
actions:
  - straight: {distance: 5.0, speed: 0.25}
  - turn: {angle_deg: 90, yaw_rate: 0.3}
  - straight: {distance: 3.0}
    until: {marker: 4}            # optional end condition
  - free_navigation: {waypoints: [[1, 2], [3, 4]], goal: {x: 5, y: 6, yaw_deg: 90}}
  - fence_navigation: {side: left, fence_distance: 0.5, distance: 10}
  - stripe_navigation: {stripe: 3, distance: 12}
    until: stripe_end
  - dock: {target: charger}
)";

// Routes are equal when all parameters match exactly (marker ids only count for marker ends).
void ExpectSameRoute(const Route& a, const Route& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.map_id, b.map_id);
  ASSERT_EQ(a.actions.size(), b.actions.size());
  for (size_t i = 0; i < a.actions.size(); ++i) {
    SCOPED_TRACE(i);
    const RouteAction& x = a.actions[i];
    const RouteAction& y = b.actions[i];
    ASSERT_EQ(x.params.index(), y.params.index());
    EXPECT_EQ(x.end.kind, y.end.kind);
    if (x.end.kind == EndConditionKind::kMarkerDetected) {
      EXPECT_EQ(x.end.marker_id, y.end.marker_id);
    }
    if (const auto* t = std::get_if<TurnAction>(&x.params)) {
      const auto& u = std::get<TurnAction>(y.params);
      EXPECT_EQ(t->angle_rad, u.angle_rad);
      EXPECT_EQ(t->yaw_rate_radps, u.yaw_rate_radps);
    } else if (const auto* s = std::get_if<StraightAction>(&x.params)) {
      const auto& u = std::get<StraightAction>(y.params);
      EXPECT_EQ(s->distance_m, u.distance_m);
      EXPECT_EQ(s->speed_mps, u.speed_mps);
    } else if (const auto* n = std::get_if<FreeNavigationAction>(&x.params)) {
      const auto& u = std::get<FreeNavigationAction>(y.params);
      EXPECT_EQ(n->waypoints_m, u.waypoints_m);
      EXPECT_EQ(n->goal.x_m(), u.goal.x_m());
      EXPECT_EQ(n->goal.y_m(), u.goal.y_m());
      EXPECT_EQ(n->goal.yaw_rad(), u.goal.yaw_rad());
      EXPECT_EQ(n->speed_mps, u.speed_mps);
    } else if (const auto* f = std::get_if<FenceNavigationAction>(&x.params)) {
      const auto& u = std::get<FenceNavigationAction>(y.params);
      EXPECT_EQ(f->side, u.side);
      EXPECT_EQ(f->fence_distance_m, u.fence_distance_m);
      EXPECT_EQ(f->distance_m, u.distance_m);
      EXPECT_EQ(f->speed_mps, u.speed_mps);
    } else if (const auto* p = std::get_if<StripeNavigationAction>(&x.params)) {
      const auto& u = std::get<StripeNavigationAction>(y.params);
      EXPECT_EQ(p->stripe_id, u.stripe_id);
      EXPECT_EQ(p->distance_m, u.distance_m);
      EXPECT_EQ(p->speed_mps, u.speed_mps);
    } else {
      const auto& d = std::get<DockAction>(x.params);
      const auto& u = std::get<DockAction>(y.params);
      EXPECT_EQ(d.target, u.target);
      EXPECT_EQ(d.target_id, u.target_id);
    }
  }
}

TEST(RouteYamlTest, ParsesTheDocumentedExample) {
  absl::StatusOr<Route> route = ParseRouteYaml(kExample);
  ASSERT_TRUE(route.ok()) << route.status();
  EXPECT_EQ(route->name, "feed-round-1");
  EXPECT_EQ(route->map_id, "barn");
  ASSERT_EQ(route->actions.size(), 7u);

  const auto& straight = std::get<StraightAction>(route->actions[0].params);
  EXPECT_DOUBLE_EQ(straight.distance_m, 5.0);
  EXPECT_DOUBLE_EQ(straight.speed_mps, 0.25);
  EXPECT_EQ(route->actions[0].end.kind, EndConditionKind::kDistance);

  const auto& turn = std::get<TurnAction>(route->actions[1].params);
  EXPECT_NEAR(turn.angle_rad, kPi / 2.0, 1e-12);
  EXPECT_DOUBLE_EQ(turn.yaw_rate_radps, 0.3);

  EXPECT_EQ(route->actions[2].end.kind, EndConditionKind::kMarkerDetected);
  EXPECT_EQ(route->actions[2].end.marker_id, 4);
  EXPECT_DOUBLE_EQ(std::get<StraightAction>(route->actions[2].params).speed_mps, 0.25);

  const auto& navigation = std::get<FreeNavigationAction>(route->actions[3].params);
  ASSERT_EQ(navigation.waypoints_m.size(), 2u);
  EXPECT_EQ(navigation.waypoints_m[1], Eigen::Vector2d(3, 4));
  EXPECT_TRUE(navigation.goal.IsNear(Pose2(5, 6, kPi / 2.0), 1e-12, 1e-12));
  EXPECT_EQ(route->actions[3].end.kind, EndConditionKind::kGoalReached);

  const auto& fence = std::get<FenceNavigationAction>(route->actions[4].params);
  EXPECT_EQ(fence.side, Side::kLeft);
  EXPECT_DOUBLE_EQ(fence.fence_distance_m, 0.5);
  EXPECT_DOUBLE_EQ(fence.distance_m, 10.0);

  const auto& stripe = std::get<StripeNavigationAction>(route->actions[5].params);
  EXPECT_EQ(stripe.stripe_id, 3);
  EXPECT_EQ(route->actions[5].end.kind, EndConditionKind::kStripeEnd);

  EXPECT_EQ(std::get<DockAction>(route->actions[6].params).target, DockTarget::kCharger);
  EXPECT_EQ(route->actions[6].end.kind, EndConditionKind::kChargerContact);
}

TEST(RouteYamlTest, AcceptsRadiansAndOtherEndConditions) {
  absl::StatusOr<Route> route = ParseRouteYaml(R"(name: r
actions:
  - turn: {angle_rad: -1.25}
  - fence_navigation: {side: right, distance: 0}
    until: {marker: 2}
  - dock: {target: trolley, target_id: cart-7}
  - free_navigation: {goal: {x: 1, y: 2, yaw_rad: 0.5}}
    until: goal_reached
  - straight: {distance: 2}
    until: distance
  - undock: {}
  - undock:
)");
  ASSERT_TRUE(route.ok()) << route.status();
  EXPECT_DOUBLE_EQ(std::get<TurnAction>(route->actions[0].params).angle_rad, -1.25);
  EXPECT_EQ(std::get<FenceNavigationAction>(route->actions[1].params).side, Side::kRight);
  EXPECT_EQ(route->actions[1].end.marker_id, 2);
  EXPECT_EQ(std::get<DockAction>(route->actions[2].params).target_id, "cart-7");
  EXPECT_EQ(route->actions[2].end.kind, EndConditionKind::kGoalReached);
  EXPECT_DOUBLE_EQ(std::get<FreeNavigationAction>(route->actions[3].params).goal.yaw_rad(), 0.5);
  EXPECT_TRUE(std::holds_alternative<UndockAction>(route->actions[5].params));
  EXPECT_TRUE(std::holds_alternative<UndockAction>(route->actions[6].params));
  EXPECT_EQ(route->actions[5].end.kind, EndConditionKind::kDistance);
  EXPECT_TRUE(route->map_id.empty());
  // Written back and read again, the undock stays an undock; it takes no parameters.
  absl::StatusOr<Route> back = ParseRouteYaml(RouteToYaml(*route));
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_TRUE(std::holds_alternative<UndockAction>(back->actions[6].params));
  const absl::StatusOr<Route> bad =
      ParseRouteYaml("name: r\nactions:\n  - undock: {height: 0.1}\n");
  EXPECT_EQ(bad.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(bad.status().message().find("height"), std::string::npos) << bad.status();
}

TEST(RouteYamlTest, WaypointsMayFixTheYawThere) {
  absl::StatusOr<Route> route = ParseRouteYaml(
      "name: r\nmap: m\nactions:\n"
      "  - free_navigation: {waypoints: [[1, 2], [3, 4, 90]], goal: {x: 5, y: 6, yaw_deg: 0}}\n");
  ASSERT_TRUE(route.ok()) << route.status();
  const auto& nav = std::get<FreeNavigationAction>(route->actions[0].params);
  EXPECT_FALSE(nav.WaypointYaw(0).has_value());
  ASSERT_TRUE(nav.WaypointYaw(1).has_value());
  EXPECT_NEAR(*nav.WaypointYaw(1), (kPi / 2), 1e-12);
  absl::StatusOr<Route> back = ParseRouteYaml(RouteToYaml(*route));
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_NEAR(*std::get<FreeNavigationAction>(back->actions[0].params).WaypointYaw(1), (kPi / 2),
              1e-9);
  EXPECT_EQ(ParseRouteYaml("name: r\nmap: m\nactions:\n  - free_navigation: {waypoints: "
                           "[[1, 2, 3, 4]], goal: {x: 5, y: 6}}\n")
                .status()
                .code(),
            absl::StatusCode::kInvalidArgument);
}

TEST(RouteYamlTest, RejectsUnknownActionType) {
  ExpectInvalid(ParseRouteYaml("name: r\nactions:\n  - straight: {distance: 1}\n"
                               "  - jump: {height: 2}\n"),
                "actions[1]: unknown action type 'jump'");
}

TEST(RouteYamlTest, RejectsUnknownKeys) {
  ExpectInvalid(ParseRouteYaml("name: r\nactions:\n  - turn: {angel_deg: 90}\n"),
                "actions[0] (turn): unknown key 'angel_deg'");
  ExpectInvalid(ParseRouteYaml("name: r\nactions:\n  - straight: {distance: 1}\n    speed: 2\n"),
                "actions[0] (straight): unknown key 'speed'");
  ExpectInvalid(ParseRouteYaml("name: r\nactions:\n  - free_navigation: {goal: {x: 1, y: 2, "
                               "z: 3}}\n"),
                "actions[0] (free_navigation): goal: unknown key 'z'");
  ExpectInvalid(ParseRouteYaml("name: r\nowner: me\nactions:\n  - straight: {distance: 1}\n"),
                "unknown key 'owner'");
  ExpectInvalid(ParseRouteYaml("name: r\nactions:\n  - straight: {distance: 1}\n"
                               "    until: {stripe: 3}\n"),
                "actions[0] (straight): until: unknown key 'stripe'");
}

TEST(RouteYamlTest, RejectsMalformedActions) {
  ExpectInvalid(ParseRouteYaml("name: r\nactions:\n  - turn: {angle_deg: 90}\n"
                               "    straight: {distance: 1}\n"),
                "actions[0]: more than one action type");
  ExpectInvalid(ParseRouteYaml("name: r\nactions:\n  - until: stripe_end\n"),
                "actions[0]: missing the action type");
  ExpectInvalid(ParseRouteYaml("name: r\nactions:\n  - turn: {angle_deg: 90, angle_rad: 1}\n"),
                "give either 'angle_deg' or 'angle_rad', not both");
  ExpectInvalid(ParseRouteYaml("name: r\nactions:\n  - turn: {yaw_rate: 1}\n"),
                "actions[0] (turn): missing 'angle_deg' (or 'angle_rad')");
  ExpectInvalid(ParseRouteYaml("name: r\nactions:\n  - straight: {distance: far}\n"),
                "actions[0] (straight): distance: expected a number, got 'far'");
  ExpectInvalid(
      ParseRouteYaml("name: r\nactions:\n  - fence_navigation: {side: up, distance: 1}\n"),
      "side must be left or right, got 'up'");
  ExpectInvalid(ParseRouteYaml("name: r\nactions:\n  - dock: {target: moon}\n"),
                "target must be charger or trolley, got 'moon'");
  ExpectInvalid(ParseRouteYaml("name: r\nactions:\n  - straight: {distance: 1}\n"
                               "    until: marker\n"),
                "a marker end needs its id");
  ExpectInvalid(ParseRouteYaml("name: r\nactions:\n  - straight: {distance: 1}\n"
                               "    until: forever\n"),
                "actions[0] (straight): until: unknown end condition 'forever'");
  ExpectInvalid(ParseRouteYaml("name: r\nactions:\n  - straight\n"),
                "actions[0]: expected a mapping");
}

TEST(RouteYamlTest, RejectsInvalidRoutesWithTheValidationMessage) {
  ExpectInvalid(ParseRouteYaml("name: r\nactions:\n  - turn: {angle_deg: 90}\n"
                               "  - turn: {angle_deg: 45}\n  - straight: {distance: 0}\n"),
                "actions[2] (straight): distance_m must be > 0");
  ExpectInvalid(ParseRouteYaml("name: r\nactions:\n  - dock: {target: charger}\n"
                               "    until: stripe_end\n"),
                "actions[0] (dock): end condition 'stripe_end'");
  ExpectInvalid(ParseRouteYaml("actions:\n  - turn: {angle_deg: 90}\n"), "missing 'name'");
  ExpectInvalid(ParseRouteYaml("name: r\nactions: []\n"), "actions must not be empty");
  ExpectInvalid(ParseRouteYaml("name: r\n"), "missing 'actions'");
  ExpectInvalid(ParseRouteYaml("name: [r\n"), "YAML syntax error");
}

TEST(RouteYamlTest, ExampleRoundTrips) {
  absl::StatusOr<Route> route = ParseRouteYaml(kExample);
  ASSERT_TRUE(route.ok()) << route.status();
  const std::string yaml = RouteToYaml(*route);
  absl::StatusOr<Route> again = ParseRouteYaml(yaml);
  ASSERT_TRUE(again.ok()) << again.status() << "\n" << yaml;
  ExpectSameRoute(*again, *route);
  EXPECT_EQ(RouteToYaml(*again), yaml);
  // Whole degrees stay readable.
  EXPECT_THAT(yaml, HasSubstr("turn: {angle_deg: 90, yaw_rate: 0.3}"));
  EXPECT_THAT(yaml, HasSubstr("until: {marker: 4}"));
}

TEST(RouteYamlTest, ConstructedRouteRoundTripsExactly) {
  Route route;
  route.name = "night: patrol #2";  // needs quoting
  route.map_id = "store-7";
  route.actions = {
      RouteAction{TurnAction{0.123456789, 0.45}, {EndConditionKind::kMarkerDetected, -3}},
      RouteAction{StraightAction{1.0 / 3.0, 0.1}, {}},
      RouteAction{FreeNavigationAction{{{0.1, 0.2}}, Pose2(-1e-3, 2e5, -2.5), 0.7},
                  {EndConditionKind::kDistance, 0}},
      RouteAction{FenceNavigationAction{Side::kRight, 0.45, 0.0, 0.2},
                  {EndConditionKind::kStripeEnd, 0}},
      RouteAction{StripeNavigationAction{9, 4.5, 0.3}, {EndConditionKind::kMarkerDetected, 12}},
      RouteAction{DockAction{DockTarget::kTrolley, "trolley: blue"}, {}},
      RouteAction{DockAction{DockTarget::kCharger, ""}, {EndConditionKind::kChargerContact, 0}},
  };
  ASSERT_TRUE(route.Validate().ok()) << route.Validate();
  const std::string yaml = RouteToYaml(route);
  absl::StatusOr<Route> parsed = ParseRouteYaml(yaml);
  ASSERT_TRUE(parsed.ok()) << parsed.status() << "\n" << yaml;
  ExpectSameRoute(*parsed, route);
}

TEST(RouteFileTest, SaveThenLoad) {
  const std::filesystem::path path =
      std::filesystem::path(::testing::TempDir()) / "fleetnav_route_io_save_then_load.yaml";
  absl::StatusOr<Route> route = ParseRouteYaml(kExample);
  ASSERT_TRUE(route.ok());
  ASSERT_TRUE(SaveRoute(*route, path.string()).ok());
  absl::StatusOr<Route> loaded = LoadRoute(path.string());
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  ExpectSameRoute(*loaded, *route);
  std::filesystem::remove(path);
  EXPECT_EQ(LoadRoute(path.string()).status().code(), absl::StatusCode::kNotFound);
}

TEST(RouteFileTest, SaveRefusesInvalidRoute) {
  Route route;
  route.name = "broken";
  route.actions = {RouteAction{StraightAction{0.0, 0.25}, {}}};
  const absl::Status status = SaveRoute(
      route,
      (std::filesystem::path(::testing::TempDir()) / "fleetnav_route_io_broken.yaml").string());
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(status.message()), HasSubstr("actions[0] (straight)"));
}

}  // namespace
}  // namespace fleetnav
