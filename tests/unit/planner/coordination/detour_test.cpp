#include "fleetnav/planner/coordination/detour.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/planner/coordination/route_prediction.hpp"
#include "fleetnav/planner/grid/costmap.hpp"
#include "fleetnav/planner/single_robot/planner_factory.hpp"

namespace fleetnav::planner {
namespace {

constexpr double kCellM = 0.2;
constexpr double kMarginM = 0.5;

/// A 16 x 8 m hall (0.05 m cells, origin (-8, -4)): walls round it and a shelf block north of
/// y = 0.8 from x = -5 to 5, so a lane 4.75 m wide runs along the south wall below it.
OccupancyGrid Hall() {
  OccupancyGrid grid =
      OccupancyGrid::Filled(320, 160, 0.05, Pose2(-8.0, -4.0, 0.0), OccupancyGrid::kFreeValue)
          .value();
  for (int y = 0; y < 160; ++y) {
    for (int x = 0; x < 320; ++x) {
      const double wx = -8.0 + 0.05 * (x + 0.5);
      const double wy = -4.0 + 0.05 * (y + 0.5);
      const bool wall = x < 2 || y < 2 || x >= 318 || y >= 158;
      const bool shelf = std::abs(wx) < 5.0 && wy > 0.8;
      if (wall || shelf) grid.SetValue({x, y}, OccupancyGrid::kOccupiedValue);
    }
  }
  return grid;
}

/// The path the robot drives through `waypoints` to `goal` on the map alone (as the agent and
/// fleetnavd's prediction plan it).
std::vector<Pose2> Drive(const OccupancyGrid& grid, const RobotModel& model, const Pose2& from,
                         const std::vector<Eigen::Vector2d>& waypoints, const Pose2& goal) {
  CostmapParams params;
  params.padding_m = 0.1;
  Costmap costmap = Costmap::Build(grid, model.footprint_m, params).value();
  std::unique_ptr<SingleRobotPlanner> planner =
      MakeSingleRobotPlanner(&costmap, model, NavigationPlannerParams(model)).value();
  absl::StatusOr<WaypointPath> path =
      PlanThroughWaypoints(*planner, grid.origin(), from, waypoints, goal, 1.0, {});
  EXPECT_TRUE(path.ok()) << path.status();
  return path.ok() ? path->poses : std::vector<Pose2>{};
}

TEST(DetourTest, AWayRoundARobotStandingInTheLaneKeepsTheMarginOffIt) {
  const OccupancyGrid grid = Hall();
  const RobotModel model = MecanumPlatformModel();
  const Pose2 from(-6.0, -1.0, 0.0);
  FreeNavigationAction action;
  action.goal = Pose2(6.0, -1.0, 0.0);
  // One stands on the straight way, as a platform parked in the lane.
  const Pose2 standing_at(0.0, -1.0, kPi / 2.0);
  const CellSet standing = CellSet::Sweep({standing_at}, model.footprint_m, 0.2, kCellM);
  const CellSet kept_off = CellSet::Sweep({standing_at}, model.footprint_m, 0.2 + kMarginM, kCellM);
  // The way the map alone gives passes through it.
  const std::vector<Pose2> direct = Drive(grid, model, from, {}, action.goal);
  ASSERT_TRUE(CellSet::Sweep(direct, model.footprint_m, kMarginM, kCellM).Intersects(standing));

  absl::StatusOr<std::vector<Eigen::Vector2d>> waypoints =
      PlanDetour(grid, model, {&kept_off}, kCellM, from, action);
  ASSERT_TRUE(waypoints.ok()) << waypoints.status();
  // A few corners, not a waypoint every metre: each leg through them is a search.
  ASSERT_GE(waypoints->size(), 1u);
  EXPECT_LE(waypoints->size(), 6u);
  // Driven through the waypoints on the map alone, the way sweeps clear of it.
  const std::vector<Pose2> round = Drive(grid, model, from, *waypoints, action.goal);
  EXPECT_FALSE(CellSet::Sweep(round, model.footprint_m, kMarginM, kCellM).Intersects(standing));
  for (const Eigen::Vector2d& w : *waypoints) {
    EXPECT_GT((w - from.translation()).norm(), 0.3);
    EXPECT_GT((w - action.goal.translation()).norm(), 0.3);
  }
}

TEST(DetourTest, NoWayRoundRobotsAcrossTheLaneIsNotFound) {
  const OccupancyGrid grid = Hall();
  const RobotModel model = MecanumPlatformModel();
  // Robots standing across the whole lane below the shelf block.
  std::vector<CellSet> across;
  for (double y = -3.6; y <= 0.6; y += 0.6) {
    across.push_back(CellSet::Sweep({Pose2(0.0, y, 0.0)}, model.footprint_m, 0.3, kCellM));
  }
  std::vector<const CellSet*> blocked;
  for (const CellSet& cells : across) blocked.push_back(&cells);
  FreeNavigationAction action;
  action.goal = Pose2(3.0, -1.0, 0.0);
  absl::StatusOr<std::vector<Eigen::Vector2d>> waypoints =
      PlanDetour(grid, model, blocked, kCellM, Pose2(-3.0, -1.0, 0.0), action);
  EXPECT_TRUE(absl::IsNotFound(waypoints.status())) << waypoints.status();
  EXPECT_NE(waypoints.status().message().find("no way round the robots that stand"),
            std::string::npos);
}

TEST(DetourTest, ARobotStandingCloseBesideTheStartDoesNotTrapIt) {
  const OccupancyGrid grid = Hall();
  const RobotModel model = MecanumPlatformModel();
  const Pose2 from(-6.0, -1.0, 0.0);
  // Its neighbour's grown floor reaches under the robot's own footprint.
  const CellSet beside =
      CellSet::Sweep({Pose2(-6.0, -0.2, 0.0)}, model.footprint_m, 0.2 + kMarginM, kCellM);
  ASSERT_TRUE(CellSet::Sweep({from}, model.footprint_m, 0.0, kCellM).Intersects(beside));
  FreeNavigationAction action;
  action.goal = Pose2(-2.0, -2.5, 0.0);
  absl::StatusOr<std::vector<Eigen::Vector2d>> waypoints =
      PlanDetour(grid, model, {&beside}, kCellM, from, action);
  EXPECT_TRUE(waypoints.ok()) << waypoints.status();
}

/// A platform on the hall planning a way from (x_m, -1) 6 m east (or as far as x = 3).
absl::StatusOr<std::vector<Eigen::Vector2d>> EastFrom(double x_m, const DetourParams& params = {}) {
  FreeNavigationAction action;
  action.goal = Pose2(3.0, -1.0, 0.0);
  return PlanDetour(Hall(), MecanumPlatformModel(), {}, kCellM, Pose2(x_m, -1.0, 0.0), action,
                    params);
}

TEST(DetourTest, BadInputIsRefusedNamingIt) {
  DetourParams params;
  params.max_leg_m = 0.0;
  absl::StatusOr<std::vector<Eigen::Vector2d>> got = EastFrom(-3.0, params);
  EXPECT_TRUE(absl::IsInvalidArgument(got.status()));
  EXPECT_NE(got.status().message().find("max_leg_m"), std::string::npos);
  got = EastFrom(30.0);
  EXPECT_TRUE(absl::IsInvalidArgument(got.status()));
  EXPECT_NE(got.status().message().find("outside the map"), std::string::npos);
  params = {};
  params.max_expansions = 0;
  got = EastFrom(-3.0, params);
  EXPECT_TRUE(absl::IsInvalidArgument(got.status()));
  EXPECT_NE(got.status().message().find("max_expansions"), std::string::npos);
}

// The search ends on its expansion budget, not the wall clock: the same way round, or none,
// however busy the machine is.
TEST(DetourTest, TheSearchEndsOnItsExpansionBudget) {
  DetourParams starved;
  starved.max_expansions = 10;
  starved.time_limit_s = 1000.0;
  const absl::StatusOr<std::vector<Eigen::Vector2d>> got = EastFrom(-3.0, starved);
  EXPECT_TRUE(absl::IsNotFound(got.status())) << got.status();
  EXPECT_TRUE(EastFrom(-3.0).ok());
}

TEST(DetourTest, AStraightWayNeedsNoWaypointsAndTheActionsOwnAreKept) {
  const OccupancyGrid grid = Hall();
  const RobotModel model = MecanumPlatformModel();
  const Costmap costmap = Costmap::Build(grid, model.footprint_m, CostmapParams{}).value();
  std::vector<Pose2> poses;
  for (int i = 0; i <= 100; ++i) poses.emplace_back(-6.0 + 0.1 * i, -2.0, 0.0);  // 10 m east
  DetourParams long_legs;
  long_legs.max_leg_m = 20.0;
  EXPECT_TRUE(ThinToWaypoints(poses, costmap, grid.origin(), long_legs).empty());
  // The longest leg bounds a straight way.
  DetourParams short_legs;
  short_legs.max_leg_m = 3.0;
  const std::vector<Eigen::Vector2d> legs =
      ThinToWaypoints(poses, costmap, grid.origin(), short_legs);
  EXPECT_EQ(legs.size(), 3u);
  for (const Eigen::Vector2d& p : legs) EXPECT_NEAR(p.y(), -2.0, 1e-9);
  // A waypoint of the action's own is kept where the path passes it.
  const std::vector<Eigen::Vector2d> kept =
      ThinToWaypoints(poses, costmap, grid.origin(), long_legs, {{-1.0, -1.9}});
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_DOUBLE_EQ(kept[0].x(), -1.0);
  EXPECT_DOUBLE_EQ(kept[0].y(), -1.9);
  EXPECT_TRUE(ThinToWaypoints({Pose2()}, costmap, grid.origin(), DetourParams{}).empty());
}

}  // namespace
}  // namespace fleetnav::planner
