#include "fleetnav/planner/grid/coarse_grid.hpp"

#include <gtest/gtest.h>

#include "fleetnav/core/angles.hpp"

namespace fleetnav::planner {
namespace {

OccupancyGrid OpenGrid(int width, int height, double resolution_m, Pose2 origin = Pose2()) {
  return *OccupancyGrid::Filled(width, height, resolution_m, origin, OccupancyGrid::kFreeValue);
}

TEST(CoarseGridTest, ACellIsFreeOnlyIfEveryMapCellInItIs) {
  OccupancyGrid grid = OpenGrid(10, 10, 0.1);
  grid.SetValue({7, 2}, OccupancyGrid::kOccupiedValue);  // in coarse cell (1, 0)
  grid.SetValue({1, 8}, OccupancyGrid::kUnknownValue);   // in coarse cell (0, 1)
  const CoarseGrid coarse = Coarsen(grid, 0.5);
  EXPECT_DOUBLE_EQ(coarse.cell_m, 0.5);
  ASSERT_EQ(coarse.map.width, 2);
  ASSERT_EQ(coarse.map.height, 2);
  EXPECT_TRUE(coarse.map.passable[0]);
  EXPECT_FALSE(coarse.map.passable[1]);
  EXPECT_FALSE(coarse.map.passable[2]);
  EXPECT_TRUE(coarse.map.passable[3]);
}

TEST(CoarseGridTest, CellsAreAWholeNumberOfMapCellsAndPartialCellsAtTheEdgeAreDropped) {
  const CoarseGrid coarse = Coarsen(OpenGrid(11, 7, 0.1), 0.25);
  EXPECT_NEAR(coarse.cell_m, 0.3, 1e-12);  // three map cells: never smaller than asked
  EXPECT_EQ(coarse.map.width, 3);
  EXPECT_EQ(coarse.map.height, 2);
  // Finer than the map: the map's own cells.
  EXPECT_NEAR(Coarsen(OpenGrid(4, 4, 0.1), 0.05).cell_m, 0.1, 1e-12);
}

TEST(CoarseGridTest, CellsFollowARotatedOrigin) {
  const CoarseGrid coarse = Coarsen(OpenGrid(20, 20, 0.1, Pose2(5.0, -1.0, kPi / 2)), 0.5);
  const Eigen::Vector2d centre = coarse.CenterOf(1, 2);
  // Map x runs along world +y, map y along world -x.
  EXPECT_NEAR(centre.x(), 5.0 - 1.25, 1e-9);
  EXPECT_NEAR(centre.y(), -1.0 + 0.75, 1e-9);
  int x = -1, y = -1;
  coarse.CellOf(Pose2(centre.x(), centre.y(), 0.0), &x, &y);
  EXPECT_EQ(x, 1);
  EXPECT_EQ(y, 2);
  coarse.CellOf(Pose2(5.1, -1.0, 0.0), &x, &y);  // behind the origin: off the grid
  EXPECT_LT(y, 0);
}

}  // namespace
}  // namespace fleetnav::planner
