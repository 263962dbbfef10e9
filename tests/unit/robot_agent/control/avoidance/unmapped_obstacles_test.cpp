// The obstacle layer on generated scans: returns the map explains are dropped, the others are
// marked and stay out of view, a beam through a marked cell clears it, and marking keeps the
// robot's own footprint clear.
#include "fleetnav/robot_agent/control/avoidance/unmapped_obstacles.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>

#include "fleetnav/core/angles.hpp"

namespace fleetnav::agent {
namespace {

/// 10 m × 10 m at 5 cm, free, with a mapped wall along x = 8 m.
std::shared_ptr<const OccupancyGrid> WalledMap() {
  OccupancyGrid grid =
      OccupancyGrid::Filled(200, 200, 0.05, Pose2(), OccupancyGrid::kFreeValue).value();
  for (int y = 0; y < 200; ++y) grid.SetValue({160, y}, OccupancyGrid::kOccupiedValue);
  return std::make_shared<const OccupancyGrid>(std::move(grid));
}

/// A 3-beam scan (−10°, 0°, +10°) with the given ranges (inf: no return).
LaserScanSample Scan(float right, float ahead, float left) {
  LaserScanSample scan;
  scan.angle_min_rad = DegToRad(-10.0);
  scan.angle_increment_rad = DegToRad(10.0);
  scan.range_max_m = 30.0;
  scan.ranges_m = {right, ahead, left};
  return scan;
}

constexpr float kNone = std::numeric_limits<float>::infinity();

TEST(UnmappedObstaclesTest, MarksWhatTheMapDoesNotExplainAndRemembersIt) {
  const std::shared_ptr<const OccupancyGrid> map = WalledMap();
  UnmappedObstacles layer(map, UnmappedObstaclesParams{});
  // From (2, 5) facing +x: a box 3 m ahead (not on the map) and the mapped wall 6 m away, seen
  // 5 cm off (as a pose estimate would put it).
  const Pose2 robot(2.0, 5.0, 0.0);
  const double wall_m = 6.05 / std::cos(DegToRad(10.0));
  const std::vector<Eigen::Vector2d> unexplained =
      layer.AddScan(Scan(static_cast<float>(wall_m), 3.0F, kNone), Pose2(), robot);
  ASSERT_EQ(unexplained.size(), 1U);
  EXPECT_NEAR(unexplained[0].x(), 3.0, 1e-6);
  EXPECT_EQ(layer.size(), 1U);

  // Turned away, the box is out of view: still marked.
  layer.AddScan(Scan(kNone, kNone, kNone), Pose2(), Pose2(2.0, 5.0, kPi));
  EXPECT_EQ(layer.size(), 1U);
  OccupancyGrid grid = *map;
  const Eigen::AlignedBox2d small(Eigen::Vector2d(-0.3, -0.3), Eigen::Vector2d(0.3, 0.3));
  EXPECT_EQ(layer.MarkOn(grid, robot, small), 1);
  EXPECT_EQ(grid.StateAtWorld({5.0, 5.0}), CellState::kOccupied);
}

TEST(UnmappedObstaclesTest, ABeamThroughAMarkedCellClearsIt) {
  UnmappedObstacles layer(WalledMap(), UnmappedObstaclesParams{});
  layer.AddScan(Scan(kNone, 3.0F, kNone), Pose2(), Pose2(2.0, 5.0, 0.0));
  ASSERT_EQ(layer.size(), 1U);
  // The box has gone: the beam now reaches the mapped wall through its cell.
  layer.AddScan(Scan(kNone, 6.0F, kNone), Pose2(), Pose2(2.0, 5.0, 0.0));
  EXPECT_EQ(layer.size(), 0U);
}

TEST(UnmappedObstaclesTest, MarkingKeepsTheRobotsFootprintClear) {
  const std::shared_ptr<const OccupancyGrid> map = WalledMap();
  UnmappedObstacles layer(map, UnmappedObstaclesParams{});
  layer.AddScan(Scan(kNone, 0.5F, kNone), Pose2(), Pose2(2.0, 5.0, 0.0));
  ASSERT_EQ(layer.size(), 1U);
  OccupancyGrid grid = *map;
  // A footprint to x = 0.45 m with a 0.1 m margin.
  const Eigen::AlignedBox2d keep_clear(Eigen::Vector2d(-0.3, -0.4), Eigen::Vector2d(0.55, 0.4));
  // 5 cm beyond the nose, within the margin: left clear.
  EXPECT_EQ(layer.MarkOn(grid, Pose2(2.0, 5.0, 0.0), keep_clear), 0);
  // From 1 m further back it is an obstacle ahead.
  EXPECT_EQ(layer.MarkOn(grid, Pose2(1.0, 5.0, 0.0), keep_clear), 1);
}

}  // namespace
}  // namespace fleetnav::agent
