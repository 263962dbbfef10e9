// SiteCache reads each version once, follows the latest versions written through it, forgets a
// deleted map's versions, and stays within its byte budget.
#include "fleetnav/server/site/site_cache.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "fleetnav/storage/memory/memory_fleet_repositories.hpp"
#include "fleetnav/storage/memory/memory_map_repository.hpp"

namespace fleetnav::server {
namespace {

/// Counts the reads that reach the store.
class CountingMaps : public storage::MapRepository {
 public:
  absl::StatusOr<MapInfo> PutMap(const std::string& id, const OccupancyGrid& grid,
                                 const std::string& description, int64_t created_unix_ms) override {
    return inner.PutMap(id, grid, description, created_unix_ms);
  }
  absl::StatusOr<storage::StoredMap> GetMap(const std::string& id, uint32_t version) override {
    ++reads;
    return inner.GetMap(id, version);
  }
  absl::StatusOr<std::vector<MapInfo>> ListMaps() override { return inner.ListMaps(); }
  absl::Status DeleteMap(const std::string& id) override { return inner.DeleteMap(id); }

  storage::MemoryMapRepository inner;
  int reads = 0;
};

class CountingRoutes : public storage::RouteRepository {
 public:
  absl::StatusOr<uint32_t> PutRoute(const Route& route, int64_t created_unix_ms) override {
    return inner.PutRoute(route, created_unix_ms);
  }
  absl::StatusOr<storage::StoredRoute> GetRoute(const std::string& name,
                                                uint32_t version) override {
    ++reads;
    return inner.GetRoute(name, version);
  }
  absl::StatusOr<std::vector<storage::StoredRoute>> ListRoutes(const std::string& map) override {
    return inner.ListRoutes(map);
  }
  absl::StatusOr<int> CountRoutesOnMap(const std::string& map) override {
    return inner.CountRoutesOnMap(map);
  }
  absl::Status DeleteRoute(const std::string& name) override { return inner.DeleteRoute(name); }

  storage::MemoryRouteRepository inner;
  int reads = 0;
};

OccupancyGrid Grid(int side, int8_t value) {
  absl::StatusOr<OccupancyGrid> grid = OccupancyGrid::Create(
      side, side, 0.1, Pose2(), std::vector<int8_t>(static_cast<size_t>(side * side), value));
  EXPECT_TRUE(grid.ok());
  return *grid;
}

Route StraightRoute(const std::string& name, int actions) {
  Route route;
  route.name = name;
  route.map_id = "barn";
  for (int i = 0; i < actions; ++i) {
    route.actions.push_back({StraightAction{1.0, 0.3}, {EndConditionKind::kDistance}});
  }
  return route;
}

class SiteCacheTest : public ::testing::Test {
 protected:
  CountingMaps maps_;
  storage::MemoryMarkerSetRepository markers_;
  CountingRoutes routes_;
};

TEST_F(SiteCacheTest, AVersionIsReadFromTheStoreOnce) {
  SiteCache cache(&maps_, &markers_, &routes_);
  ASSERT_TRUE(cache.PutMap("barn", Grid(10, 0), "", 0).ok());
  for (int i = 0; i < 5; ++i) {
    absl::StatusOr<std::shared_ptr<const storage::StoredMap>> map = cache.Map("barn", 0);
    ASSERT_TRUE(map.ok()) << map.status();
    EXPECT_EQ((*map)->info.version, 1u);
    EXPECT_EQ(cache.LatestMapVersion("barn").value_or(0), 1u);
  }
  EXPECT_EQ(maps_.reads, 1);
  // Two reads of one version share one copy.
  EXPECT_EQ(cache.Map("barn", 1)->get(), cache.Map("barn", 0)->get());
}

TEST_F(SiteCacheTest, LatestVersionsFollowTheWritesThroughTheCache) {
  SiteCache cache(&maps_, &markers_, &routes_);
  ASSERT_TRUE(cache.PutRoute(StraightRoute("round", 3), 0).ok());
  EXPECT_EQ((*cache.RouteVersion("round", 0))->route.actions.size(), 3u);
  ASSERT_TRUE(cache.PutRoute(StraightRoute("round", 7), 0).ok());
  absl::StatusOr<std::shared_ptr<const storage::StoredRoute>> latest =
      cache.RouteVersion("round", 0);
  ASSERT_TRUE(latest.ok());
  EXPECT_EQ((*latest)->version, 2u);
  EXPECT_EQ((*latest)->route.actions.size(), 7u);
  EXPECT_EQ((*cache.RouteVersion("round", 1))->route.actions.size(), 3u);

  EXPECT_EQ(cache.LatestMarkerSetVersion("barn"), 0u);
  MarkerSet set;
  set.map_id = "barn";
  StripeMarker marker;
  marker.id = 4;
  set.markers.push_back(marker);
  ASSERT_TRUE(cache.PutMarkerSet(set, 0).ok());
  EXPECT_EQ(cache.LatestMarkerSetVersion("barn"), 1u);
}

TEST_F(SiteCacheTest, ADeletedMapIsForgottenSoItsNewVersionOneIsRead) {
  SiteCache cache(&maps_, &markers_, &routes_);
  ASSERT_TRUE(cache.PutMap("barn", Grid(10, 0), "", 0).ok());
  ASSERT_TRUE(cache.Map("barn", 1).ok());
  ASSERT_TRUE(cache.DeleteMap("barn").ok());
  EXPECT_EQ(cache.Map("barn", 0).status().code(), absl::StatusCode::kNotFound);
  ASSERT_TRUE(cache.PutMap("barn", Grid(10, 100), "", 0).ok());
  absl::StatusOr<std::shared_ptr<const storage::StoredMap>> again = cache.Map("barn", 1);
  ASSERT_TRUE(again.ok()) << again.status();
  EXPECT_EQ((*again)->grid, Grid(10, 100));
}

TEST_F(SiteCacheTest, TheBudgetKeepsTheMostRecentlyUsed) {
  SiteCacheParams params;
  params.budget_bytes = 2 * (100 * 100 + 256);  // two 100×100 maps
  SiteCache cache(&maps_, &markers_, &routes_, params);
  for (const char* id : {"a", "b", "c"}) ASSERT_TRUE(cache.PutMap(id, Grid(100, 0), "", 0).ok());
  ASSERT_TRUE(cache.Map("a", 1).ok());
  ASSERT_TRUE(cache.Map("b", 1).ok());
  ASSERT_TRUE(cache.Map("a", 1).ok());  // a is now more recent than b
  ASSERT_TRUE(cache.Map("c", 1).ok());  // b leaves
  EXPECT_LE(cache.held_bytes(), params.budget_bytes);
  const int reads = maps_.reads;
  ASSERT_TRUE(cache.Map("a", 1).ok());
  ASSERT_TRUE(cache.Map("c", 1).ok());
  EXPECT_EQ(maps_.reads, reads);
  ASSERT_TRUE(cache.Map("b", 1).ok());
  EXPECT_EQ(maps_.reads, reads + 1);

  // Larger than the whole budget: served, not kept.
  ASSERT_TRUE(cache.PutMap("huge", Grid(200, 0), "", 0).ok());
  ASSERT_TRUE(cache.Map("huge", 1).ok());
  ASSERT_TRUE(cache.Map("huge", 1).ok());
  EXPECT_EQ(maps_.reads, reads + 3);
  EXPECT_LE(cache.held_bytes(), params.budget_bytes);
}

}  // namespace
}  // namespace fleetnav::server
