#include "fleetnav/core/occupancy_grid.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "fleetnav/core/angles.hpp"

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

void ExpectInvalid(const absl::StatusOr<OccupancyGrid>& grid, const std::string& needle) {
  ASSERT_FALSE(grid.ok());
  EXPECT_EQ(grid.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(grid.status().message()), HasSubstr(needle));
}

OccupancyGrid MakeGrid(int width, int height, double resolution_m, const Pose2& origin) {
  absl::StatusOr<OccupancyGrid> grid =
      OccupancyGrid::Filled(width, height, resolution_m, origin, OccupancyGrid::kFreeValue);
  EXPECT_TRUE(grid.ok()) << grid.status();
  return *std::move(grid);
}

TEST(OccupancyGridTest, CreateKeepsFields) {
  const std::vector<int8_t> cells = {0, 100, -1, 50, 0, 0};
  absl::StatusOr<OccupancyGrid> grid = OccupancyGrid::Create(3, 2, 0.05, Pose2(1, 2, 0.5), cells);
  ASSERT_TRUE(grid.ok()) << grid.status();
  EXPECT_EQ(grid->width(), 3);
  EXPECT_EQ(grid->height(), 2);
  EXPECT_DOUBLE_EQ(grid->resolution_m(), 0.05);
  EXPECT_DOUBLE_EQ(grid->width_m(), 0.15);
  EXPECT_DOUBLE_EQ(grid->height_m(), 0.10);
  EXPECT_EQ(grid->cells(), cells);
  EXPECT_EQ(grid->Value({1, 0}), 100);
  EXPECT_EQ(grid->Value({0, 1}), 50);  // row-major: index = y * width + x
  EXPECT_DOUBLE_EQ(grid->origin().yaw_rad(), 0.5);
}

TEST(OccupancyGridTest, RejectsNonPositiveSize) {
  ExpectInvalid(OccupancyGrid::Create(0, 2, 0.05, Pose2(), {}), "width must be > 0");
  ExpectInvalid(OccupancyGrid::Create(2, -1, 0.05, Pose2(), {}), "height must be > 0, got -1");
}

TEST(OccupancyGridTest, RejectsTooManyCellsWithoutAllocating) {
  ExpectInvalid(OccupancyGrid::Filled(100'000, 100'000, 0.05, Pose2(), 0), "exceeds the limit");
  ExpectInvalid(OccupancyGrid::Create(20'000, 10'000, 0.05, Pose2(), {}), "exceeds the limit");
}

TEST(OccupancyGridTest, RejectsBadResolution) {
  ExpectInvalid(OccupancyGrid::Create(1, 1, std::nan(""), Pose2(), {0}),
                "resolution_m must be finite and > 0, got nan");
  ExpectInvalid(OccupancyGrid::Create(1, 1, -0.05, Pose2(), {0}),
                "resolution_m must be finite and > 0, got -0.05");
  ExpectInvalid(OccupancyGrid::Create(1, 1, 0.0, Pose2(), {0}), "resolution_m");
  ExpectInvalid(OccupancyGrid::Create(1, 1, std::numeric_limits<double>::infinity(), Pose2(), {0}),
                "resolution_m");
}

TEST(OccupancyGridTest, RejectsNonFiniteOrigin) {
  ExpectInvalid(OccupancyGrid::Create(1, 1, 0.05, Pose2(std::nan(""), 0, 0), {0}), "origin");
}

TEST(OccupancyGridTest, RejectsCellCountMismatch) {
  ExpectInvalid(OccupancyGrid::Create(3, 2, 0.05, Pose2(), {0, 0, 0, 0, 0}),
                "cells.size() = 5 does not match width*height = 6");
}

TEST(OccupancyGridTest, RejectsCellValuesOutsideRange) {
  ExpectInvalid(OccupancyGrid::Create(2, 2, 0.05, Pose2(), {0, 0, 0, 101}),
                "cells[3] = 101 is outside [-1, 100]");
  ExpectInvalid(OccupancyGrid::Create(2, 2, 0.05, Pose2(), {0, -2, 0, 0}), "cells[1] = -2");
}

TEST(OccupancyGridTest, StateThresholds) {
  const std::vector<int8_t> values = {-1, 0, 25, 26, 64, 65, 100};
  absl::StatusOr<OccupancyGrid> grid = OccupancyGrid::Create(7, 1, 0.1, Pose2(), values);
  ASSERT_TRUE(grid.ok());
  EXPECT_EQ(grid->State({0, 0}), CellState::kUnknown);
  EXPECT_EQ(grid->State({1, 0}), CellState::kFree);
  EXPECT_EQ(grid->State({2, 0}), CellState::kFree);
  EXPECT_EQ(grid->State({3, 0}), CellState::kUnknown);
  EXPECT_EQ(grid->State({4, 0}), CellState::kUnknown);
  EXPECT_EQ(grid->State({5, 0}), CellState::kOccupied);
  EXPECT_EQ(grid->State({6, 0}), CellState::kOccupied);
}

TEST(OccupancyGridTest, SetValueAndInBounds) {
  OccupancyGrid grid = MakeGrid(4, 3, 0.1, Pose2());
  grid.SetValue({3, 2}, OccupancyGrid::kOccupiedValue);
  EXPECT_EQ(grid.State({3, 2}), CellState::kOccupied);
  EXPECT_TRUE(grid.InBounds({0, 0}));
  EXPECT_TRUE(grid.InBounds({3, 2}));
  EXPECT_FALSE(grid.InBounds({4, 0}));
  EXPECT_FALSE(grid.InBounds({0, 3}));
  EXPECT_FALSE(grid.InBounds({-1, 0}));
}

TEST(OccupancyGridTest, WorldToCellWithoutRotationUsesFloor) {
  const OccupancyGrid grid = MakeGrid(10, 5, 0.5, Pose2(-1.0, 2.0, 0.0));
  EXPECT_EQ(grid.WorldToCell({-1.0, 2.0}), (CellIndex{0, 0}));
  EXPECT_EQ(grid.WorldToCell({-0.51, 2.49}), (CellIndex{0, 0}));
  EXPECT_EQ(grid.WorldToCell({-0.5, 2.5}), (CellIndex{1, 1}));
  EXPECT_EQ(grid.WorldToCell({3.99, 4.49}), (CellIndex{9, 4}));
  EXPECT_FALSE(grid.WorldToCell({-1.01, 2.0}).has_value());  // floor, not truncation
  EXPECT_FALSE(grid.WorldToCell({-1.0, 1.99}).has_value());
  EXPECT_FALSE(grid.WorldToCell({4.0, 3.0}).has_value());  // upper edge is outside
  EXPECT_FALSE(grid.WorldToCell({0.0, 4.5}).has_value());
  EXPECT_FALSE(grid.WorldToCell({std::nan(""), 3.0}).has_value());
  EXPECT_FALSE(grid.WorldToCell({1e300, 3.0}).has_value());
}

TEST(OccupancyGridTest, WorldToCellRespectsRotatedOrigin) {
  // The grid's x axis points along map +y: origin at (10, 5) with yaw 90 degrees.
  const OccupancyGrid grid = MakeGrid(4, 2, 0.1, Pose2(10.0, 5.0, kPi / 2.0));
  // Grid-frame point (0.25, 0.05) is cell (2, 0); in the map it is (10 - 0.05, 5 + 0.25).
  EXPECT_EQ(grid.WorldToCell({9.95, 5.25}), (CellIndex{2, 0}));
  // Grid-frame point (0.35, 0.15) is cell (3, 1).
  EXPECT_EQ(grid.WorldToCell({9.85, 5.35}), (CellIndex{3, 1}));
  // Without the rotation these map points would be outside; with it, points at x > 10 are.
  EXPECT_FALSE(grid.WorldToCell({10.05, 5.25}).has_value());
  EXPECT_FALSE(grid.WorldToCell({9.95, 4.95}).has_value());
  EXPECT_FALSE(grid.ContainsWorld({10.2, 5.1}));
  EXPECT_TRUE(grid.ContainsWorld({9.9, 5.1}));
}

TEST(OccupancyGridTest, CellToWorldIsInverseOfWorldToCellForRotatedGrid) {
  const OccupancyGrid grid = MakeGrid(13, 7, 0.25, Pose2(-3.0, 4.0, 0.7));
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      const Eigen::Vector2d centre = grid.CellToWorld({x, y});
      EXPECT_EQ(grid.WorldToCell(centre), (CellIndex{x, y}));
    }
  }
  const Eigen::Vector2d first = grid.CellToWorld({0, 0});
  const Eigen::Vector2d expected = Pose2(-3.0, 4.0, 0.7).TransformPoint({0.125, 0.125});
  EXPECT_NEAR((first - expected).norm(), 0.0, 1e-12);
}

TEST(OccupancyGridTest, StateAtWorldOutsideIsUnknown) {
  OccupancyGrid grid = MakeGrid(2, 2, 1.0, Pose2());
  grid.SetValue({1, 1}, OccupancyGrid::kOccupiedValue);
  EXPECT_EQ(grid.StateAtWorld({0.5, 0.5}), CellState::kFree);
  EXPECT_EQ(grid.StateAtWorld({1.5, 1.5}), CellState::kOccupied);
  EXPECT_EQ(grid.StateAtWorld({2.5, 0.5}), CellState::kUnknown);
}

TEST(OccupancyGridTest, Equality) {
  const OccupancyGrid a = MakeGrid(3, 3, 0.1, Pose2(1, 1, 0));
  OccupancyGrid b = MakeGrid(3, 3, 0.1, Pose2(1, 1, 0));
  EXPECT_TRUE(a == b);
  b.SetValue({0, 0}, -1);
  EXPECT_FALSE(a == b);
  EXPECT_FALSE(a == MakeGrid(3, 3, 0.1, Pose2(1, 1, 0.1)));
  EXPECT_FALSE(a == MakeGrid(3, 3, 0.2, Pose2(1, 1, 0)));
}

}  // namespace
}  // namespace fleetnav
