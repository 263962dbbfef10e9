// SiteCatalog's versioning of marker sets and routes.
#include "fleetnav/server/site_catalog.hpp"

#include <gtest/gtest.h>

#include "fleetnav/core/clock.hpp"
#include "fleetnav/server/map_catalog.hpp"
#include "fleetnav/server/site_cache.hpp"
#include "fleetnav/storage/memory/memory_fleet_repositories.hpp"
#include "fleetnav/storage/memory/memory_map_repository.hpp"

namespace fleetnav::server {
namespace {

class SiteCatalogTest : public ::testing::Test {
 protected:
  void SetUp() override {
    OccupancyGrid grid = OccupancyGrid::Filled(100, 100, 0.1, Pose2(), 0).value();
    ASSERT_TRUE(MapCatalog(&site_data_, &clock_).Put("hall", grid, "").ok());
  }

  static Route Alley(double distance_m) {
    Route route;
    route.name = "alley";
    route.map_id = "hall";
    route.actions.push_back(RouteAction{StraightAction{distance_m, 0.25}, {}});
    return route;
  }
  static MarkerSet Markers(double x_m) {
    MarkerSet markers;
    markers.map_id = "hall";
    StripeMarker marker;
    marker.id = 1;
    marker.position_m = Eigen::Vector2d(x_m, 2.0);
    markers.markers.push_back(marker);
    return markers;
  }

  ManualClock clock_;
  storage::MemoryMapRepository map_store_;
  storage::MemoryMarkerSetRepository marker_store_;
  storage::MemoryRouteRepository route_store_;
  storage::MemoryJobRepository job_store_;
  SiteCache site_data_{&map_store_, &marker_store_, &route_store_};
  SiteCatalog site_{&site_data_, &job_store_, &clock_};
};

TEST_F(SiteCatalogTest, TheSameRouteAgainIsTheVersionThatHoldsIt) {
  EXPECT_EQ(site_.PutRoute(Alley(3.0)).value(), 1u);
  EXPECT_EQ(site_.PutRoute(Alley(3.0)).value(), 1u);
  EXPECT_EQ(site_.PutRoute(Alley(3.5)).value(), 2u);
  EXPECT_EQ(site_.PutRoute(Alley(3.0)).value(), 3u);  // only the latest is compared
  EXPECT_EQ(site_.ListRoutes("hall").value().size(), 1u);
}

TEST_F(SiteCatalogTest, TheSameMarkerSetAgainIsTheVersionThatHoldsIt) {
  EXPECT_EQ(site_.PutMarkerSet(Markers(1.0)).value(), 1u);
  EXPECT_EQ(site_.PutMarkerSet(Markers(1.0)).value(), 1u);
  EXPECT_EQ(site_.PutMarkerSet(Markers(1.5)).value(), 2u);
  EXPECT_EQ(site_.LatestMarkerSetVersion("hall"), 2u);
}

}  // namespace
}  // namespace fleetnav::server
