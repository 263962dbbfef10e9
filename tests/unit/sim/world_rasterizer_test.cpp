#include "fleetnav/sim/world_rasterizer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "fleetnav/core/angles.hpp"

namespace fleetnav::sim {
namespace {

WorldDescription EmptyWorld() {
  WorldDescription world;
  world.name = "test";
  world.min_corner_m = Eigen::Vector2d(-5, -4);
  world.max_corner_m = Eigen::Vector2d(5, 4);
  return world;
}

CellState StateAt(const OccupancyGrid& grid, double x, double y) {
  return grid.StateAtWorld(Eigen::Vector2d(x, y));
}

int CountOccupied(const OccupancyGrid& grid) {
  return static_cast<int>(
      std::count(grid.cells().begin(), grid.cells().end(), OccupancyGrid::kOccupiedValue));
}

TEST(WorldRasterizerTest, GridCoversTheExtent) {
  absl::StatusOr<OccupancyGrid> grid = RasterizeWorld(EmptyWorld(), 0.1);
  ASSERT_TRUE(grid.ok()) << grid.status();
  EXPECT_EQ(grid->width(), 100);
  EXPECT_EQ(grid->height(), 80);
  EXPECT_DOUBLE_EQ(grid->resolution_m(), 0.1);
  EXPECT_TRUE(grid->origin().IsNear(Pose2(-5, -4, 0), 1e-12, 1e-12));
  // No obstacles: every cell free.
  EXPECT_EQ(CountOccupied(*grid), 0);
  EXPECT_TRUE(std::all_of(grid->cells().begin(), grid->cells().end(),
                          [](int8_t v) { return v == OccupancyGrid::kFreeValue; }));

  absl::StatusOr<OccupancyGrid> coarse = RasterizeWorld(EmptyWorld(), 0.25);
  ASSERT_TRUE(coarse.ok());
  EXPECT_EQ(coarse->width(), 40);
  EXPECT_EQ(coarse->height(), 32);

  // An extent that is not a whole number of cells is covered by one more cell.
  WorldDescription odd = EmptyWorld();
  odd.max_corner_m = Eigen::Vector2d(5.05, 4);
  absl::StatusOr<OccupancyGrid> odd_grid = RasterizeWorld(odd, 0.1);
  ASSERT_TRUE(odd_grid.ok());
  EXPECT_EQ(odd_grid->width(), 101);
}

TEST(WorldRasterizerTest, WallCellsOccupiedAndFreeSpaceFree) {
  WorldDescription world = EmptyWorld();
  // A 4 m wall along x at y = 0, 0.2 m thick.
  world.boxes.push_back({"wall", Eigen::Vector2d(0, 0), Eigen::Vector2d(4, 0.2), 0.0, 2.5});
  absl::StatusOr<OccupancyGrid> grid = RasterizeWorld(world, 0.1);
  ASSERT_TRUE(grid.ok()) << grid.status();
  // The two rows of cells whose centres lie inside the wall, 40 cells each.
  EXPECT_EQ(StateAt(*grid, 0.05, 0.05), CellState::kOccupied);
  EXPECT_EQ(StateAt(*grid, 0.05, -0.05), CellState::kOccupied);
  EXPECT_EQ(StateAt(*grid, -1.95, 0.05), CellState::kOccupied);
  EXPECT_EQ(StateAt(*grid, 1.95, -0.05), CellState::kOccupied);
  EXPECT_EQ(CountOccupied(*grid), 80);
  // Beside and beyond the wall is free.
  EXPECT_EQ(StateAt(*grid, 0.05, 0.15), CellState::kFree);
  EXPECT_EQ(StateAt(*grid, 0.05, -0.15), CellState::kFree);
  EXPECT_EQ(StateAt(*grid, 2.05, 0.05), CellState::kFree);
  EXPECT_EQ(StateAt(*grid, -3.0, 2.0), CellState::kFree);
}

TEST(WorldRasterizerTest, CylinderOccupied) {
  WorldDescription world = EmptyWorld();
  world.cylinders.push_back({"post", Eigen::Vector2d(3, 2), 0.3, 1.5});
  absl::StatusOr<OccupancyGrid> grid = RasterizeWorld(world, 0.05);
  ASSERT_TRUE(grid.ok()) << grid.status();
  EXPECT_EQ(StateAt(*grid, 3.01, 2.01), CellState::kOccupied);
  EXPECT_EQ(StateAt(*grid, 3.26, 2.01), CellState::kOccupied);
  EXPECT_EQ(StateAt(*grid, 3.36, 2.01), CellState::kFree);
  // Diagonal: inside the bounding square but outside the circle.
  EXPECT_EQ(StateAt(*grid, 3.26, 2.26), CellState::kFree);
  // Area close to π r² (0.283 m² = 113 cells of 0.05 m).
  EXPECT_NEAR(CountOccupied(*grid), kPi * 0.3 * 0.3 / (0.05 * 0.05), 12);
}

TEST(WorldRasterizerTest, ALegThinnerThanACellBetweenCellCentresIsOnTheMap) {
  // A trolley leg of 2 cm radius on a 5 cm map, its centre on a cell corner: it covers no
  // cell's centre, but a laser would see it, so the four cells it touches are occupied.
  WorldDescription world = EmptyWorld();
  world.cylinders.push_back({"leg", Eigen::Vector2d(1.0, 1.0), 0.02, 1.0});
  absl::StatusOr<OccupancyGrid> grid = RasterizeWorld(world, 0.05);
  ASSERT_TRUE(grid.ok()) << grid.status();
  EXPECT_EQ(CountOccupied(*grid), 4);
  for (const double dx : {-0.025, 0.025}) {
    for (const double dy : {-0.025, 0.025}) {
      EXPECT_EQ(StateAt(*grid, 1.0 + dx, 1.0 + dy), CellState::kOccupied);
    }
  }
}

TEST(WorldRasterizerTest, RotatedBox) {
  WorldDescription world = EmptyWorld();
  // A 2 m × 0.2 m box at (-3, 2) turned by 45°.
  world.boxes.push_back(
      {"box", Eigen::Vector2d(-3, 2), Eigen::Vector2d(2, 0.2), DegToRad(45), 1.0});
  absl::StatusOr<OccupancyGrid> grid = RasterizeWorld(world, 0.05);
  ASSERT_TRUE(grid.ok()) << grid.status();
  const double d = 0.8 / std::sqrt(2.0);  // 0.8 m along the box's own x
  EXPECT_EQ(StateAt(*grid, -3 + d, 2 + d), CellState::kOccupied);
  EXPECT_EQ(StateAt(*grid, -3 - d, 2 - d), CellState::kOccupied);
  // On the world x axis through the centre 0.8 m out: inside an unrotated box, outside this one.
  EXPECT_EQ(StateAt(*grid, -3 + 0.8, 2), CellState::kFree);
  EXPECT_EQ(StateAt(*grid, -3 + d, 2 - d), CellState::kFree);
  // Area close to 2 × 0.2 m² = 160 cells.
  EXPECT_NEAR(CountOccupied(*grid), 2.0 * 0.2 / (0.05 * 0.05), 25);
}

TEST(WorldRasterizerTest, BarnHasItsFencesAndPole) {
  absl::StatusOr<WorldDescription> barn =
      LoadWorld(std::string(FLEETNAV_WORLDS_DIR) + "/barn.yaml");
  ASSERT_TRUE(barn.ok()) << barn.status();
  absl::StatusOr<OccupancyGrid> grid = RasterizeWorld(*barn, 0.05);
  ASSERT_TRUE(grid.ok()) << grid.status();
  EXPECT_EQ(grid->width(), 520);
  EXPECT_EQ(grid->height(), 520);
  EXPECT_EQ(StateAt(*grid, 0.01, 5.91), CellState::kOccupied);    // north fence
  EXPECT_EQ(StateAt(*grid, 0.01, 4.71), CellState::kFree);        // the alley beside it
  EXPECT_EQ(StateAt(*grid, -11.49, 0.01), CellState::kOccupied);  // charging pole
  EXPECT_EQ(StateAt(*grid, 11.01, 0.01), CellState::kOccupied);   // feed kitchen
  EXPECT_EQ(StateAt(*grid, -12.89, 0.01), CellState::kOccupied);  // west wall
  EXPECT_EQ(StateAt(*grid, -5.5, 0.01), CellState::kFree);        // the robot's spawn
}

TEST(WorldRasterizerTest, MarkerSetOfCarriesTheMarkers) {
  absl::StatusOr<WorldDescription> barn =
      LoadWorld(std::string(FLEETNAV_WORLDS_DIR) + "/barn.yaml");
  ASSERT_TRUE(barn.ok()) << barn.status();
  const MarkerSet set = MarkerSetOf(*barn, "barn-map");
  EXPECT_EQ(set.map_id, "barn-map");
  // The three calibration markers, then one piece per straight part of each stripe: stripes
  // 1-6 and the charger stripe 9 are straight, the arcs 7 and 8 have six pieces each.
  ASSERT_EQ(set.markers.size(), 3u + 7u + 12u);
  ASSERT_NE(set.Find(2), nullptr);
  EXPECT_EQ(set.Find(2)->position_m, Eigen::Vector2d(5.0, 4.7));
  EXPECT_EQ(set.Find(2)->kind, MarkerKind::kCalibration);
  int arc_pieces = 0, charger_pieces = 0;
  for (const StripeMarker& m : set.markers) {
    if (m.kind == MarkerKind::kCalibration) {
      EXPECT_EQ(m.stripe_id, 0);
      continue;
    }
    EXPECT_GT(m.id, 3);
    if (m.stripe_id == 7) ++arc_pieces;
    if (m.kind == MarkerKind::kChargerStripe) {
      ++charger_pieces;
      EXPECT_EQ(m.stripe_id, 9);
      EXPECT_NEAR(m.length_m, 4.6, 1e-9);
      EXPECT_NEAR(m.position_m.x(), -8.3, 1e-9);
    }
    if (m.stripe_id == 1) {
      EXPECT_EQ(m.kind, MarkerKind::kFollowStripe);
      EXPECT_NEAR(m.length_m, 20.0, 1e-9);
      EXPECT_NEAR(m.yaw_rad, 0.0, 1e-9);
    }
  }
  EXPECT_EQ(arc_pieces, 6);
  EXPECT_EQ(charger_pieces, 1);
  EXPECT_TRUE(set.Validate().ok()) << set.Validate();
  // The pieces survive the marker YAML.
  absl::StatusOr<MarkerSet> parsed = ParseMarkerSetYaml(MarkerSetToYaml(set));
  ASSERT_TRUE(parsed.ok()) << parsed.status();
  ASSERT_EQ(parsed->markers.size(), set.markers.size());
  EXPECT_EQ(parsed->markers.back().stripe_id, 9);
}

}  // namespace
}  // namespace fleetnav::sim
