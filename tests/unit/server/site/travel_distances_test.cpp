// TravelDistances: path lengths over the map for the dispatcher — around walls, not through
// them; nothing for places off the map or walled off.
#include "fleetnav/server/site/travel_distances.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "fleetnav/storage/memory/memory_fleet_repositories.hpp"
#include "fleetnav/storage/memory/memory_map_repository.hpp"

namespace fleetnav::server {
namespace {

/// A 20 × 10 m site (0.1 m cells) with a wall along x = 10 m from y = 0 to y = 8 m, and a closed
/// 2 × 2 m room at (15..17, 2..4).
OccupancyGrid Site() {
  OccupancyGrid grid = *OccupancyGrid::Filled(200, 100, 0.1, Pose2(), OccupancyGrid::kFreeValue);
  for (int y = 0; y < 80; ++y) grid.SetValue({100, y}, OccupancyGrid::kOccupiedValue);
  for (int i = 150; i <= 170; ++i) {
    grid.SetValue({i, 20}, OccupancyGrid::kOccupiedValue);
    grid.SetValue({i, 40}, OccupancyGrid::kOccupiedValue);
  }
  for (int j = 20; j <= 40; ++j) {
    grid.SetValue({150, j}, OccupancyGrid::kOccupiedValue);
    grid.SetValue({170, j}, OccupancyGrid::kOccupiedValue);
  }
  return grid;
}

class TravelDistancesTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(cache_.PutMap("site", Site(), "", 0).ok()); }

  storage::MemoryMapRepository maps_;
  storage::MemoryMarkerSetRepository markers_;
  storage::MemoryRouteRepository routes_;
  SiteCache cache_{&maps_, &markers_, &routes_};
  TravelDistances travel_{&cache_};
};

TEST_F(TravelDistancesTest, OpenFloorIsAboutTheStraightLine) {
  const std::optional<double> d = travel_.Between("site", {2.0, 1.0}, {5.0, 5.0});
  ASSERT_TRUE(d.has_value());
  EXPECT_GE(*d, 5.0 - 0.5);
  EXPECT_LE(*d, 5.0 * 1.1 + 0.5);  // octile steps on 0.5 m cells
}

TEST_F(TravelDistancesTest, AWallIsGoneAroundNotThrough) {
  // 2 m apart in a straight line, but the way round the wall's end at y = 8 m is about 16 m.
  const std::optional<double> d = travel_.Between("site", {9.0, 1.0}, {11.0, 1.0});
  ASSERT_TRUE(d.has_value());
  EXPECT_GT(*d, 15.0);
  EXPECT_LT(*d, 19.0);
  // The same field serves another robot for the same destination.
  const std::optional<double> near = travel_.Between("site", {12.0, 2.0}, {11.0, 1.0});
  ASSERT_TRUE(near.has_value());
  EXPECT_LT(*near, 2.5);
}

TEST_F(TravelDistancesTest, NoPathOffTheMapIntoAClosedRoomOrOnAnUnknownMap) {
  EXPECT_FALSE(travel_.Between("site", {2.0, 1.0}, {25.0, 1.0}).has_value());
  EXPECT_FALSE(travel_.Between("site", {2.0, 1.0}, {16.0, 3.0}).has_value());
  EXPECT_FALSE(travel_.Between("nowhere", {2.0, 1.0}, {3.0, 1.0}).has_value());
}

TEST_F(TravelDistancesTest, ARobotBesideAWallStartsFromTheFreeCellNextToIt) {
  // 9.95 m lies in the coarse cell that holds the wall.
  const std::optional<double> d = travel_.Between("site", {9.95, 9.0}, {9.0, 9.0});
  ASSERT_TRUE(d.has_value());
  EXPECT_LT(*d, 2.0);
}

}  // namespace
}  // namespace fleetnav::server
