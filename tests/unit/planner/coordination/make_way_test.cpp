#include "fleetnav/planner/coordination/make_way.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "fleetnav/core/occupancy_grid.hpp"

namespace fleetnav::planner {
namespace {

const std::vector<Eigen::Vector2d> kSquare{{-0.4, -0.4}, {0.4, -0.4}, {0.4, 0.4}, {-0.4, 0.4}};
constexpr double kCellM = 0.2;
constexpr double kMarginM = 0.3;

/// A 20 x 10 m floor (0.1 m cells, origin (-10, -5)): an aisle 2.4 m wide between two shelf
/// blocks from x = -6 to 6 m, open floor at both ends.
OccupancyGrid AisleFloor() {
  OccupancyGrid grid =
      OccupancyGrid::Filled(200, 100, 0.1, Pose2(-10.0, -5.0, 0.0), OccupancyGrid::kFreeValue)
          .value();
  for (int y = 0; y < 100; ++y) {
    for (int x = 0; x < 200; ++x) {
      const double wx = -10.0 + 0.1 * (x + 0.5);
      const double wy = -5.0 + 0.1 * (y + 0.5);
      const bool border = x < 1 || y < 1 || x >= 199 || y >= 99;
      const bool shelf = std::abs(wx) < 6.0 && std::abs(wy) > 1.2 && std::abs(wy) < 3.0;
      if (border || shelf) grid.SetValue({x, y}, OccupancyGrid::kOccupiedValue);
    }
  }
  return grid;
}

/// The cells a robot sweeps driving from `from` to `to`, grown by the margin.
CellSet Way(Eigen::Vector2d from, Eigen::Vector2d to) {
  std::vector<Pose2> poses;
  for (int i = 0; i <= 40; ++i) {
    const Eigen::Vector2d p = from + (to - from) * (i / 40.0);
    poses.emplace_back(p.x(), p.y(), 0.0);
  }
  return CellSet::Sweep(poses, kSquare, kMarginM, kCellM);
}

Costmap AisleCostmap(const OccupancyGrid& grid) {
  return Costmap::Build(grid, kSquare, CostmapParams{}).value();
}

TEST(MakeWayTest, ARobotIsNotSentPastOneThatStandsInTheAisle) {
  // As above, but a robot stands at the aisle's east end (the one that waits): the nearer
  // end is past it, so the place is out at the west end.
  const OccupancyGrid grid = AisleFloor();
  Costmap costmap = AisleCostmap(grid);
  const CellSet way = Way({-9.0, 0.0}, {9.0, 0.0});
  const CellSet other = CellSet::Sweep({Pose2(5.0, 0.0, 0.0)}, kSquare, 0.2, kCellM);
  MakeWayRequestGeometry request{Pose2(2.0, 0.0, 0.0), kSquare,  kMarginM, kCellM,
                                 {&way, &other},       {&other}, kMarginM};
  absl::StatusOr<Pose2> place = FindMakeWayPlace(costmap, grid.origin(), request);
  ASSERT_TRUE(place.ok()) << place.status();
  EXPECT_LT(place->x_m(), -6.0);
  EXPECT_FALSE(CellSet::Sweep({*place}, kSquare, kMarginM, kCellM).Intersects(way));
  // Without knowing where it stands, the east end is nearer.
  request.impassable.clear();
  place = FindMakeWayPlace(costmap, grid.origin(), request);
  ASSERT_TRUE(place.ok()) << place.status();
  EXPECT_GT(place->x_m(), 6.0);
}

TEST(MakeWayTest, ARobotAHairInsideAWayIsSentClearOfItNotACellAside) {
  // On open floor, a way along y = 0 and a robot whose grown footprint reaches just into it.
  const OccupancyGrid grid = AisleFloor();
  Costmap costmap = AisleCostmap(grid);
  const CellSet way = Way({-9.5, 0.0}, {-6.5, 0.0});
  const double y_m = 0.4 + kMarginM + 0.4 + kMarginM - 0.05;  // 5 cm inside, before the cells
  MakeWayRequestGeometry request{Pose2(-8.0, y_m, 0.0), kSquare, kMarginM, kCellM, {&way}};
  ASSERT_TRUE(CellSet::Sweep({request.from_in_map}, kSquare, kMarginM, kCellM).Intersects(way));
  absl::StatusOr<Pose2> place = FindMakeWayPlace(costmap, grid.origin(), request);
  ASSERT_TRUE(place.ok()) << place.status();
  // Clear of the way with a cell to spare wherever within 0.1 m of the place the robot stops:
  // before, the answer was the place 2 cm off, which the robot reached at once, still in the way.
  for (double dx : {-0.1, 0.0, 0.1}) {
    for (double dy : {-0.1, 0.0, 0.1}) {
      const Pose2 stop(place->x_m() + dx, place->y_m() + dy, place->yaw_rad());
      EXPECT_FALSE(CellSet::Sweep({stop}, kSquare, kMarginM, kCellM).Intersects(way))
          << dx << ", " << dy;
    }
  }
}

TEST(MakeWayTest, ARobotInAnAisleAnotherDrivesThroughGoesToTheNearestEndOutOfTheWay) {
  const OccupancyGrid grid = AisleFloor();
  Costmap costmap = AisleCostmap(grid);
  const CellSet way = Way({-9.0, 0.0}, {9.0, 0.0});  // down the aisle's middle, end to end
  MakeWayRequestGeometry request{Pose2(2.0, 0.0, 0.0), kSquare, kMarginM, kCellM, {&way}};
  absl::StatusOr<Pose2> place = FindMakeWayPlace(costmap, grid.origin(), request);
  ASSERT_TRUE(place.ok()) << place.status();
  // No room beside the way in a 2.4 m aisle: out at its east end (nearer than the west one),
  // off the way, on free floor.
  EXPECT_GT(place->x_m(), 6.0);
  EXPECT_FALSE(CellSet::Sweep({*place}, kSquare, kMarginM, kCellM).Intersects(way));
  EXPECT_TRUE(costmap.PoseFree(place->x_m() + 10.0, place->y_m() + 5.0, place->yaw_rad()));
  // Within a few metres of the aisle's end: the nearest such place, not any.
  EXPECT_LT(place->x_m(), 7.5);

  // From the west half it leaves by the west end.
  request.from_in_map = Pose2(-2.0, 0.0, 0.0);
  place = FindMakeWayPlace(costmap, grid.origin(), request);
  ASSERT_TRUE(place.ok()) << place.status();
  EXPECT_LT(place->x_m(), -6.0);
}

TEST(MakeWayTest, ARobotOutOfEveryonesWayStaysWhereItIs) {
  const OccupancyGrid grid = AisleFloor();
  Costmap costmap = AisleCostmap(grid);
  const CellSet way = Way({-9.0, 4.0}, {9.0, 4.0});  // along the north wall
  MakeWayRequestGeometry request{Pose2(2.0, 0.0, 0.3), kSquare, kMarginM, kCellM, {&way}};
  absl::StatusOr<Pose2> place = FindMakeWayPlace(costmap, grid.origin(), request);
  ASSERT_TRUE(place.ok()) << place.status();
  EXPECT_NEAR(place->x_m(), 2.0, 0.1);
  EXPECT_NEAR(place->y_m(), 0.0, 0.1);
  EXPECT_NEAR(place->yaw_rad(), 0.3, 1e-9);
}

TEST(MakeWayTest, NoPlaceOffTheWaysIsNotFoundNamingWhere) {
  const OccupancyGrid grid = AisleFloor();
  Costmap costmap = AisleCostmap(grid);
  // Ways over the whole floor.
  std::vector<CellSet> ways;
  for (double y = -4.5; y <= 4.5; y += 0.5) ways.push_back(Way({-9.5, y}, {9.5, y}));
  MakeWayRequestGeometry request{Pose2(2.0, 0.0, 0.0), kSquare, kMarginM, kCellM, {}};
  for (const CellSet& way : ways) request.keep_off.push_back(&way);
  absl::StatusOr<Pose2> place = FindMakeWayPlace(costmap, grid.origin(), request);
  EXPECT_EQ(place.status().code(), absl::StatusCode::kNotFound);
  EXPECT_NE(place.status().message().find("(2.00, 0.00)"), std::string::npos) << place.status();

  // Nor beyond the distance looked over: the aisle's ends are 4 m away.
  const CellSet way = Way({-9.0, 0.0}, {9.0, 0.0});
  request.keep_off = {&way};
  MakeWayParams near;
  near.max_distance_m = 3.0;
  EXPECT_EQ(FindMakeWayPlace(costmap, grid.origin(), request, near).status().code(),
            absl::StatusCode::kNotFound);
}

TEST(MakeWayTest, RefusesBadInput) {
  const OccupancyGrid grid = AisleFloor();
  Costmap costmap = AisleCostmap(grid);
  MakeWayRequestGeometry request{Pose2(50.0, 0.0, 0.0), kSquare, kMarginM, kCellM, {}};
  EXPECT_EQ(FindMakeWayPlace(costmap, grid.origin(), request).status().code(),
            absl::StatusCode::kInvalidArgument);
  request.from_in_map = Pose2(0.0, 0.0, 0.0);
  MakeWayParams bad;
  bad.candidate_step_m = 0.0;
  EXPECT_EQ(FindMakeWayPlace(costmap, grid.origin(), request, bad).status().code(),
            absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fleetnav::planner
