// CheckRouteOnSite on a drawn map: a 20 × 10 m hall (0.05 m cells) with its walls, a wall along
// y = 6 m from x = 0 to 16 m, and a closed 3 × 2 m room in the north-east corner (x 17-20,
// y 8-10: walls all round). A Lely robot starts at (2, 4.8) heading east, 1.2 m from the wall.
#include "fleetnav/robot_agent/route_site_check.hpp"

#include <gtest/gtest.h>

#include <memory>

#include "fleetnav/core/angles.hpp"

namespace fleetnav::agent {
namespace {

constexpr double kCellM = 0.05;

std::shared_ptr<const OccupancyGrid> Hall() {
  OccupancyGrid grid = *OccupancyGrid::Filled(400, 200, kCellM, Pose2(), 0);
  const auto wall = [&](double x0, double y0, double x1, double y1) {
    for (int x = static_cast<int>(x0 / kCellM); x <= static_cast<int>(x1 / kCellM); ++x) {
      for (int y = static_cast<int>(y0 / kCellM); y <= static_cast<int>(y1 / kCellM); ++y) {
        if (x >= 0 && y >= 0 && x < 400 && y < 200) grid.SetValue({x, y}, 100);
      }
    }
  };
  wall(0, 0, 20, 0.1);        // south
  wall(0, 9.9, 20, 10);       // north
  wall(0, 0, 0.1, 10);        // west
  wall(19.9, 0, 20, 10);      // east
  wall(0, 5.95, 16, 6.05);    // the long wall the robot follows
  wall(17.0, 8.0, 17.1, 10);  // the room's west wall
  wall(17.0, 8.0, 20, 8.1);   // the room's south wall
  return std::make_shared<const OccupancyGrid>(std::move(grid));
}

RouteContext Context() {
  RouteContext context;
  context.model = LelyVectorModel();
  context.map = Hall();
  return context;
}

Route RouteOf(std::vector<RouteAction> actions) {
  Route route;
  route.name = "r";
  route.map_id = "hall";
  route.actions = std::move(actions);
  return route;
}

RouteAction Fence(Side side, double distance_m) {
  RouteAction action;
  action.params = FenceNavigationAction{side, 0.9, distance_m, 0.25};
  return action;
}

RouteAction Turn(double angle_deg) {
  RouteAction action;
  action.params = TurnAction{DegToRad(angle_deg), 0.3};
  return action;
}

RouteAction GoTo(double x, double y) {
  RouteAction action;
  FreeNavigationAction nav;
  nav.goal = Pose2(x, y, 0.0);
  nav.speed_mps = 0.3;
  action.params = nav;
  action.end.kind = EndConditionKind::kGoalReached;
  return action;
}

const Pose2 kStart(2.0, 4.8, 0.0);

TEST(RouteSiteCheckTest, FenceLegAlongTheWallPasses) {
  EXPECT_TRUE(CheckRouteOnSite(RouteOf({Fence(Side::kLeft, 8.0)}), Context(), kStart).ok());
}

TEST(RouteSiteCheckTest, FenceLegOnTheSideWithoutAFenceIsRefused) {
  const absl::Status s = CheckRouteOnSite(RouteOf({Fence(Side::kRight, 8.0)}), Context(), kStart);
  EXPECT_EQ(s.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_NE(s.message().find("actions[0] (fence_navigation): no fence within 1.90 m on the right"),
            std::string::npos)
      << s;
}

// The prediction follows the route: after a right turn the left ultrasonic looks east along
// the wall, at nothing within 1.9 m.
TEST(RouteSiteCheckTest, FenceLegIsJudgedWhereThePreviousActionsLeaveTheRobot) {
  const absl::Status s =
      CheckRouteOnSite(RouteOf({Turn(-90.0), Fence(Side::kLeft, 2.0)}), Context(), kStart);
  EXPECT_EQ(s.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_NE(s.message().find("actions[1]"), std::string::npos) << s;
}

// A straight that ends on a marker stops wherever the marker is: the fence leg after it is not
// judged from the straight's full distance (30 m would put it through the east wall).
TEST(RouteSiteCheckTest, NothingIsJudgedAfterAnEndWhosePlaceIsUnknown) {
  RouteAction straight;
  straight.params = StraightAction{30.0, 0.25};
  straight.end.kind = EndConditionKind::kMarkerDetected;
  straight.end.marker_id = 1;
  EXPECT_TRUE(
      CheckRouteOnSite(RouteOf({straight, Fence(Side::kRight, 5.0)}), Context(), kStart).ok());
  straight.end.kind = EndConditionKind::kDistance;
  EXPECT_FALSE(
      CheckRouteOnSite(RouteOf({straight, Fence(Side::kRight, 5.0)}), Context(), kStart).ok());
}

TEST(RouteSiteCheckTest, ReachableGoalPasses) {
  EXPECT_TRUE(CheckRouteOnSite(RouteOf({GoTo(10.0, 2.0)}), Context(), kStart).ok());
  // Round the end of the long wall into the north strip.
  EXPECT_TRUE(CheckRouteOnSite(RouteOf({GoTo(8.0, 8.0)}), Context(), kStart).ok());
}

TEST(RouteSiteCheckTest, GoalInAClosedRoomIsRefused) {
  const absl::Status s = CheckRouteOnSite(RouteOf({GoTo(18.5, 9.0)}), Context(), kStart);
  EXPECT_EQ(s.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_NE(s.message().find("actions[0] (free_navigation): (18.50, 9.00) cannot be reached"),
            std::string::npos)
      << s;
}

TEST(RouteSiteCheckTest, WithoutAMapNothingIsChecked) {
  RouteContext context = Context();
  context.map = nullptr;
  EXPECT_TRUE(CheckRouteOnSite(RouteOf({Fence(Side::kRight, 8.0)}), context, kStart).ok());
}

}  // namespace
}  // namespace fleetnav::agent
