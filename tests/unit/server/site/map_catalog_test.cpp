#include "fleetnav/server/site/map_catalog.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "fleetnav/core/clock.hpp"
#include "fleetnav/storage/memory/memory_fleet_repositories.hpp"
#include "fleetnav/storage/memory/memory_map_repository.hpp"

namespace fleetnav::server {
namespace {

using ::testing::HasSubstr;

OccupancyGrid SampleGrid(int8_t fill) {
  absl::StatusOr<OccupancyGrid> grid = OccupancyGrid::Filled(4, 3, 0.05, Pose2(1, 2, 0.3), fill);
  EXPECT_TRUE(grid.ok()) << grid.status();
  return *std::move(grid);
}

void ExpectBadMapId(const absl::Status& status) {
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument) << status;
  EXPECT_THAT(std::string(status.message()), HasSubstr("map_id"));
}

/// The cache the catalog reads through, over in-memory repositories.
struct SiteData {
  explicit SiteData(storage::MapRepository* maps) : cache(maps, &markers, &routes) {}
  storage::MemoryMarkerSetRepository markers;
  storage::MemoryRouteRepository routes;
  SiteCache cache;
};

TEST(MapCatalogTest, ValidateMapIdAcceptsLowercaseDigitsUnderscoreAndDash) {
  for (const std::string& good : {std::string("barn"), std::string("a"), std::string("0"),
                                  std::string("barn_2-east"), std::string(64, 'z')}) {
    EXPECT_TRUE(MapCatalog::ValidateMapId(good).ok()) << good;
  }
}

TEST(MapCatalogTest, ValidateMapIdRejectsBadIdsNamingTheField) {
  for (const std::string& bad :
       {std::string(), std::string("Barn"), std::string(65, 'z'), std::string("a/b"),
        std::string("barn 2"), std::string("barn.1"), std::string("../etc"),
        std::string("b\xc3\xa4rn"), std::string("ba\0rn", 5)}) {
    SCOPED_TRACE("map_id '" + bad + "'");
    ExpectBadMapId(MapCatalog::ValidateMapId(bad));
  }
}

TEST(MapCatalogTest, PutReturnsVersionOneThenTwo) {
  storage::MemoryMapRepository repository;
  SiteData site(&repository);
  // A clock at 12.5 s past 2026-11-25 00:00 UTC: the stamp is its calendar, not the wall's.
  const ManualClock clock(12'500'000'000, 1'795'564'800'000);
  MapCatalog catalog(&site.cache, &clock);
  absl::StatusOr<MapInfo> first = catalog.Put("barn", SampleGrid(0), "empty barn");
  ASSERT_TRUE(first.ok()) << first.status();
  EXPECT_EQ(first->map_id, "barn");
  EXPECT_EQ(first->version, 1u);
  EXPECT_EQ(first->description, "empty barn");
  EXPECT_EQ(first->created_unix_ms, 1'795'564'812'500);

  absl::StatusOr<MapInfo> second = catalog.Put("barn", SampleGrid(100), "walls");
  ASSERT_TRUE(second.ok()) << second.status();
  EXPECT_EQ(second->version, 2u);

  absl::StatusOr<std::shared_ptr<const storage::StoredMap>> latest = catalog.Get("barn", 0);
  ASSERT_TRUE(latest.ok()) << latest.status();
  EXPECT_EQ((*latest)->info.version, 2u);
  EXPECT_EQ((*latest)->grid, SampleGrid(100));
  absl::StatusOr<std::shared_ptr<const storage::StoredMap>> v1 = catalog.Get("barn", 1);
  ASSERT_TRUE(v1.ok()) << v1.status();
  EXPECT_EQ((*v1)->grid, SampleGrid(0));
}

TEST(MapCatalogTest, PutWithBadIdStoresNothing) {
  storage::MemoryMapRepository repository;
  SiteData site(&repository);
  const SystemClock clock;
  MapCatalog catalog(&site.cache, &clock);
  ExpectBadMapId(catalog.Put("Barn", SampleGrid(0), "").status());
  ExpectBadMapId(catalog.Put("", SampleGrid(0), "").status());
  absl::StatusOr<std::vector<MapInfo>> list = repository.ListMaps();
  ASSERT_TRUE(list.ok());
  EXPECT_TRUE(list->empty());
}

TEST(MapCatalogTest, GetAndDeleteCheckTheIdFirst) {
  storage::MemoryMapRepository repository;
  SiteData site(&repository);
  const SystemClock clock;
  MapCatalog catalog(&site.cache, &clock);
  ASSERT_TRUE(catalog.Put("barn", SampleGrid(0), "").ok());
  ExpectBadMapId(catalog.Get("a/b", 0).status());
  ExpectBadMapId(catalog.Delete("BARN"));
  EXPECT_TRUE(repository.GetMap("barn", 1).ok());
}

TEST(MapCatalogTest, ListAndDeletePassThrough) {
  storage::MemoryMapRepository repository;
  SiteData site(&repository);
  const SystemClock clock;
  MapCatalog catalog(&site.cache, &clock);
  ASSERT_TRUE(catalog.Put("store", SampleGrid(0), "").ok());
  ASSERT_TRUE(catalog.Put("barn", SampleGrid(0), "").ok());
  absl::StatusOr<std::vector<MapInfo>> list = catalog.List();
  ASSERT_TRUE(list.ok()) << list.status();
  ASSERT_EQ(list->size(), 2u);
  EXPECT_EQ((*list)[0].map_id, "barn");
  EXPECT_EQ((*list)[1].map_id, "store");

  ASSERT_TRUE(catalog.Delete("barn").ok());
  const absl::Status again = catalog.Delete("barn");
  EXPECT_EQ(again.code(), absl::StatusCode::kNotFound) << again;
  EXPECT_THAT(std::string(again.message()), HasSubstr("barn"));
  EXPECT_EQ(catalog.Get("barn", 0).status().code(), absl::StatusCode::kNotFound);
  list = catalog.List();
  ASSERT_TRUE(list.ok());
  ASSERT_EQ(list->size(), 1u);
  EXPECT_EQ((*list)[0].map_id, "store");
}

}  // namespace
}  // namespace fleetnav::server

namespace fleetnav::server {
namespace {

TEST(MapCatalogTest, TheSameMapAgainIsTheVersionThatHoldsIt) {
  storage::MemoryMapRepository repository;
  SiteData site(&repository);
  const SystemClock clock;
  MapCatalog catalog(&site.cache, &clock);
  ASSERT_EQ(catalog.Put("barn", SampleGrid(0), "empty").value().version, 1u);
  EXPECT_EQ(catalog.Put("barn", SampleGrid(0), "empty").value().version, 1u);
  // A changed cell or description is a new version.
  EXPECT_EQ(catalog.Put("barn", SampleGrid(100), "empty").value().version, 2u);
  EXPECT_EQ(catalog.Put("barn", SampleGrid(100), "walls").value().version, 3u);
  EXPECT_EQ(catalog.Put("barn", SampleGrid(100), "walls").value().version, 3u);
  // Back to an older content is new: only the latest version is compared.
  EXPECT_EQ(catalog.Put("barn", SampleGrid(0), "empty").value().version, 4u);
}

}  // namespace
}  // namespace fleetnav::server
