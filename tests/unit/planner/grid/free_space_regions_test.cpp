#include "fleetnav/planner/grid/free_space_regions.hpp"

#include <gtest/gtest.h>

namespace fleetnav::planner {
namespace {

/// 10 m × 4 m at 0.1 m, a wall across x = 5 m with a door from y = 1.5 m of `door_m`.
OccupancyGrid WallWithDoor(double door_m) {
  OccupancyGrid grid = OccupancyGrid::Filled(100, 40, 0.1, Pose2(), 0).value();
  for (int y = 0; y < 40; ++y) {
    const double centre_m = (y + 0.5) * 0.1;
    if (centre_m < 1.5 || centre_m > 1.5 + door_m) {
      grid.SetValue({50, y}, OccupancyGrid::kOccupiedValue);
    }
  }
  return grid;
}

/// A square robot 0.6 m across: inscribed radius 0.3 m.
const std::vector<Eigen::Vector2d> kSquare = {{0.3, -0.3}, {0.3, 0.3}, {-0.3, 0.3}, {-0.3, -0.3}};

FreeSpaceRegions RegionsOf(const OccupancyGrid& grid) {
  absl::StatusOr<Costmap> costmap = Costmap::Build(grid, kSquare, CostmapParams{});
  EXPECT_TRUE(costmap.ok()) << costmap.status();
  return FreeSpaceRegions(*costmap);
}

TEST(FreeSpaceRegionsTest, ADoorNarrowerThanTheRobotSeparatesTheRoomsAndAWideOneJoinsThem) {
  const Eigen::Vector2d left(2.0, 2.0);
  const Eigen::Vector2d right(8.0, 2.0);
  const FreeSpaceRegions narrow = RegionsOf(WallWithDoor(0.4));
  EXPECT_FALSE(narrow.Connected(left, right));
  EXPECT_EQ(narrow.region_count(), 2);
  const FreeSpaceRegions wide = RegionsOf(WallWithDoor(1.0));
  EXPECT_TRUE(wide.Connected(left, right));
  EXPECT_EQ(wide.region_count(), 1);
}

TEST(FreeSpaceRegionsTest, APlaceNearerAWallThanTheInscribedCircleIsInNoRegionButNearOne) {
  const FreeSpaceRegions regions = RegionsOf(WallWithDoor(1.0));
  const Eigen::Vector2d beside_wall(4.85, 0.5);  // 0.1 m from the wall's face
  EXPECT_EQ(regions.RegionAt(beside_wall), FreeSpaceRegions::kNone);
  EXPECT_EQ(regions.RegionNear(beside_wall, 0.1), FreeSpaceRegions::kNone);
  EXPECT_EQ(regions.RegionNear(beside_wall, 0.3), regions.RegionAt({2.0, 2.0}));
  EXPECT_TRUE(regions.Connected(beside_wall, {8.0, 2.0}, 0.3));
  EXPECT_FALSE(regions.Connected(beside_wall, {8.0, 2.0}));
  // Off the grid: no region.
  EXPECT_EQ(regions.RegionAt({-1.0, 2.0}), FreeSpaceRegions::kNone);
  EXPECT_EQ(regions.RegionAt({2.0, 40.0}), FreeSpaceRegions::kNone);
}

}  // namespace
}  // namespace fleetnav::planner
