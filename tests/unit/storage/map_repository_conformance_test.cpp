// One conformance suite for every MapRepository implementation: the in-memory fake and the SQL
// store on SQLite (a real temporary file) and on PostgreSQL (a real server) must behave the
// same through the interface.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <memory>
#include <ostream>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "fleetnav/storage/map_repository.hpp"
#include "fleetnav/storage/memory/memory_map_repository.hpp"
#include "fleetnav/storage/sql/sql_map_repository.hpp"
#include "test_database.hpp"

namespace fleetnav::storage {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

/// Owns one repository and whatever it needs (a database file), and cleans up.
class RepositoryHarness {
 public:
  virtual ~RepositoryHarness() = default;
  virtual MapRepository& repository() = 0;
};

class MemoryHarness final : public RepositoryHarness {
 public:
  MapRepository& repository() override { return repository_; }

 private:
  MemoryMapRepository repository_;
};

/// The SQL repository on a fresh database of one engine.
class SqlHarness final : public RepositoryHarness {
 public:
  explicit SqlHarness(testing::Backend backend) : db_(backend) {
    if (db_.get() != nullptr) repository_ = std::make_unique<SqlMapRepository>(db_.get());
  }
  ~SqlHarness() override { repository_.reset(); }
  MapRepository& repository() override { return *repository_; }
  bool ready() const { return repository_ != nullptr; }

 private:
  testing::TestDatabase db_;
  std::unique_ptr<SqlMapRepository> repository_;
};

struct Implementation {
  std::string name;
  std::function<std::unique_ptr<RepositoryHarness>()> make;
};

void PrintTo(const Implementation& implementation, std::ostream* os) { *os << implementation.name; }

std::string ImplementationName(const ::testing::TestParamInfo<Implementation>& info) {
  return info.param.name;
}

OccupancyGrid Grid(int width, int height, double resolution_m, const Pose2& origin, int seed) {
  std::vector<int8_t> cells(static_cast<size_t>(width) * height);
  for (size_t i = 0; i < cells.size(); ++i) {
    const int v = static_cast<int>((i * 37 + static_cast<size_t>(seed) * 11) % 103) - 1;  // -1..101
    cells[i] = static_cast<int8_t>(std::min(v, 100));
  }
  absl::StatusOr<OccupancyGrid> grid =
      OccupancyGrid::Create(width, height, resolution_m, origin, std::move(cells));
  EXPECT_TRUE(grid.ok()) << grid.status();
  return *std::move(grid);
}

OccupancyGrid SmallGrid(int seed = 0) { return Grid(4, 3, 0.05, Pose2(1.0, -2.0, 0.5), seed); }

void ExpectNotFoundNaming(const absl::Status& status, const std::string& needle) {
  EXPECT_EQ(status.code(), absl::StatusCode::kNotFound) << status;
  EXPECT_THAT(std::string(status.message()), HasSubstr(needle));
}

class MapRepositoryConformanceTest : public ::testing::TestWithParam<Implementation> {
 protected:
  void SetUp() override {
    harness_ = GetParam().make();
    ASSERT_NE(harness_, nullptr);
  }
  MapRepository& repo() { return harness_->repository(); }

  uint32_t Put(const std::string& map_id, const OccupancyGrid& grid,
               const std::string& description = "", int64_t created_unix_ms = 0) {
    absl::StatusOr<MapInfo> info = repo().PutMap(map_id, grid, description, created_unix_ms);
    EXPECT_TRUE(info.ok()) << info.status();
    return info.ok() ? info->version : 0;
  }

  std::unique_ptr<RepositoryHarness> harness_;
};

TEST_P(MapRepositoryConformanceTest, VersionsStartAtOneAndGrowByOne) {
  absl::StatusOr<MapInfo> first = repo().PutMap("barn", SmallGrid(0), "first", 1000);
  ASSERT_TRUE(first.ok()) << first.status();
  EXPECT_EQ(first->map_id, "barn");
  EXPECT_EQ(first->version, 1u);
  EXPECT_EQ(first->width, 4);
  EXPECT_EQ(first->height, 3);
  EXPECT_EQ(first->resolution_m, 0.05);
  EXPECT_EQ(first->description, "first");
  EXPECT_EQ(first->created_unix_ms, 1000);
  EXPECT_EQ(Put("barn", SmallGrid(1)), 2u);
  EXPECT_EQ(Put("barn", SmallGrid(2)), 3u);
  // Versions count per map id.
  EXPECT_EQ(Put("store", SmallGrid(3)), 1u);
  EXPECT_EQ(Put("barn", SmallGrid(4)), 4u);
}

TEST_P(MapRepositoryConformanceTest, VersionZeroReadsTheLatest) {
  Put("barn", SmallGrid(0), "v1", 1);
  Put("barn", SmallGrid(1), "v2", 2);
  const OccupancyGrid latest = Grid(6, 2, 0.1, Pose2(0.0, 0.0, -1.0), 2);
  Put("barn", latest, "v3", 3);
  absl::StatusOr<StoredMap> got = repo().GetMap("barn", 0);
  ASSERT_TRUE(got.ok()) << got.status();
  EXPECT_EQ(got->info.version, 3u);
  EXPECT_EQ(got->info.description, "v3");
  EXPECT_EQ(got->info.created_unix_ms, 3);
  EXPECT_EQ(got->grid, latest);
}

TEST_P(MapRepositoryConformanceTest, GetsAGivenVersion) {
  const OccupancyGrid v1 = SmallGrid(0);
  const OccupancyGrid v2 = Grid(5, 5, 0.2, Pose2(3.0, 4.0, 2.0), 1);
  Put("barn", v1, "first", 10);
  Put("barn", v2, "second", 20);
  Put("barn", SmallGrid(2), "third", 30);

  absl::StatusOr<StoredMap> got1 = repo().GetMap("barn", 1);
  ASSERT_TRUE(got1.ok()) << got1.status();
  EXPECT_EQ(got1->info.version, 1u);
  EXPECT_EQ(got1->info.description, "first");
  EXPECT_EQ(got1->info.created_unix_ms, 10);
  EXPECT_EQ(got1->grid, v1);

  absl::StatusOr<StoredMap> got2 = repo().GetMap("barn", 2);
  ASSERT_TRUE(got2.ok()) << got2.status();
  EXPECT_EQ(got2->info.map_id, "barn");
  EXPECT_EQ(got2->info.version, 2u);
  EXPECT_EQ(got2->info.width, 5);
  EXPECT_EQ(got2->info.height, 5);
  EXPECT_EQ(got2->info.resolution_m, 0.2);
  EXPECT_EQ(got2->grid, v2);
}

TEST_P(MapRepositoryConformanceTest, UnknownIdIsNotFoundNamingTheId) {
  ExpectNotFoundNaming(repo().GetMap("nowhere", 0).status(), "nowhere");
  ExpectNotFoundNaming(repo().GetMap("nowhere", 1).status(), "nowhere");
  Put("barn", SmallGrid());
  ExpectNotFoundNaming(repo().GetMap("barns", 0).status(), "barns");
}

TEST_P(MapRepositoryConformanceTest, UnknownVersionIsNotFoundNamingIdAndVersion) {
  Put("barn", SmallGrid(0));
  Put("barn", SmallGrid(1));
  const absl::Status status = repo().GetMap("barn", 3).status();
  ExpectNotFoundNaming(status, "barn");
  EXPECT_THAT(std::string(status.message()), HasSubstr("3"));
  ExpectNotFoundNaming(repo().GetMap("barn", 4'000'000'000u).status(), "barn");
}

TEST_P(MapRepositoryConformanceTest, ListIsEmptyAtFirst) {
  absl::StatusOr<std::vector<MapInfo>> list = repo().ListMaps();
  ASSERT_TRUE(list.ok()) << list.status();
  EXPECT_TRUE(list->empty());
}

TEST_P(MapRepositoryConformanceTest, ListReturnsTheLatestOfEachOrderedById) {
  Put("store", SmallGrid(0), "store v1", 1);
  Put("barn", SmallGrid(1), "barn v1", 2);
  Put("barn", Grid(7, 2, 0.1, Pose2(), 2), "barn v2", 3);
  Put("yard-2", SmallGrid(3), "yard v1", 4);
  Put("store", SmallGrid(4), "store v2", 5);
  Put("store", SmallGrid(5), "store v3", 6);
  Put("a_field", SmallGrid(6), "field v1", 7);

  absl::StatusOr<std::vector<MapInfo>> list = repo().ListMaps();
  ASSERT_TRUE(list.ok()) << list.status();
  std::vector<std::string> ids;
  for (const MapInfo& info : *list) ids.push_back(info.map_id);
  EXPECT_THAT(ids, ElementsAre("a_field", "barn", "store", "yard-2"));
  ASSERT_EQ(list->size(), 4u);
  EXPECT_EQ((*list)[0].version, 1u);
  EXPECT_EQ((*list)[1].version, 2u);
  EXPECT_EQ((*list)[1].description, "barn v2");
  EXPECT_EQ((*list)[1].width, 7);
  EXPECT_EQ((*list)[1].height, 2);
  EXPECT_EQ((*list)[1].created_unix_ms, 3);
  EXPECT_EQ((*list)[2].version, 3u);
  EXPECT_EQ((*list)[2].description, "store v3");
  EXPECT_EQ((*list)[3].version, 1u);
}

TEST_P(MapRepositoryConformanceTest, DeleteRemovesEveryVersionAndOnlyThatMap) {
  Put("barn", SmallGrid(0));
  Put("barn", SmallGrid(1));
  Put("store", SmallGrid(2));
  ASSERT_TRUE(repo().DeleteMap("barn").ok());

  ExpectNotFoundNaming(repo().GetMap("barn", 0).status(), "barn");
  ExpectNotFoundNaming(repo().GetMap("barn", 1).status(), "barn");
  ExpectNotFoundNaming(repo().GetMap("barn", 2).status(), "barn");
  absl::StatusOr<std::vector<MapInfo>> list = repo().ListMaps();
  ASSERT_TRUE(list.ok()) << list.status();
  ASSERT_EQ(list->size(), 1u);
  EXPECT_EQ((*list)[0].map_id, "store");
  EXPECT_TRUE(repo().GetMap("store", 1).ok());
}

TEST_P(MapRepositoryConformanceTest, DeleteTwiceIsNotFoundNamingTheId) {
  Put("barn", SmallGrid());
  ASSERT_TRUE(repo().DeleteMap("barn").ok());
  ExpectNotFoundNaming(repo().DeleteMap("barn"), "barn");
  ExpectNotFoundNaming(repo().DeleteMap("never-stored"), "never-stored");
}

TEST_P(MapRepositoryConformanceTest, DeletedIdStartsAgainAtVersionOne) {
  Put("barn", SmallGrid(0));
  Put("barn", SmallGrid(1));
  ASSERT_TRUE(repo().DeleteMap("barn").ok());
  const OccupancyGrid fresh = SmallGrid(9);
  EXPECT_EQ(Put("barn", fresh), 1u);
  absl::StatusOr<StoredMap> got = repo().GetMap("barn", 0);
  ASSERT_TRUE(got.ok()) << got.status();
  EXPECT_EQ(got->info.version, 1u);
  EXPECT_EQ(got->grid, fresh);
}

TEST_P(MapRepositoryConformanceTest, GridRoundTripsExactly) {
  // Every cell value the grid allows, an origin with a yaw, and a resolution that is not a
  // round binary fraction.
  std::vector<int8_t> cells;
  for (int v = -1; v <= 100; ++v) cells.push_back(static_cast<int8_t>(v));
  for (int v = 100; v >= -1; --v) cells.push_back(static_cast<int8_t>(v));
  ASSERT_EQ(cells.size(), 204u);
  absl::StatusOr<OccupancyGrid> grid = OccupancyGrid::Create(
      17, 12, 0.1 / 3.0, Pose2(-12.345678901234, 98.7654321, -2.9), std::move(cells));
  ASSERT_TRUE(grid.ok()) << grid.status();

  Put("exact", *grid, "every value", 1'700'000'000'123);
  absl::StatusOr<StoredMap> got = repo().GetMap("exact", 1);
  ASSERT_TRUE(got.ok()) << got.status();
  EXPECT_EQ(got->grid.width(), 17);
  EXPECT_EQ(got->grid.height(), 12);
  EXPECT_EQ(got->grid.resolution_m(), 0.1 / 3.0);
  EXPECT_EQ(got->grid.origin().x_m(), -12.345678901234);
  EXPECT_EQ(got->grid.origin().y_m(), 98.7654321);
  EXPECT_EQ(got->grid.origin().yaw_rad(), grid->origin().yaw_rad());
  EXPECT_EQ(got->grid.cells(), grid->cells());
  EXPECT_EQ(got->grid, *grid);
  EXPECT_EQ(got->info.created_unix_ms, 1'700'000'000'123);
  EXPECT_EQ(got->info.description, "every value");
}

TEST_P(MapRepositoryConformanceTest, KeepsDescriptionsWithQuotesAndUnicode) {
  const std::string description = "O'Brien's \"barn\"; DROP TABLE maps; -- Stall Nord \xc3\xbc";
  Put("barn", SmallGrid(), description, 5);
  absl::StatusOr<StoredMap> got = repo().GetMap("barn", 1);
  ASSERT_TRUE(got.ok()) << got.status();
  EXPECT_EQ(got->info.description, description);
  EXPECT_TRUE(repo().ListMaps().ok());
}

TEST_P(MapRepositoryConformanceTest, ConcurrentPutsOnOneIdGetDistinctConsecutiveVersions) {
  constexpr int kThreads = 4;
  constexpr int kPutsPerThread = 50;
  const OccupancyGrid grid = SmallGrid();
  std::vector<std::vector<uint32_t>> versions(kThreads);
  std::vector<int> failures(kThreads, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      for (int i = 0; i < kPutsPerThread; ++i) {
        absl::StatusOr<MapInfo> info = repo().PutMap("shared", grid, "", t * 1000 + i);
        if (info.ok()) {
          versions[t].push_back(info->version);
        } else {
          ++failures[t];
        }
      }
    });
  }
  for (std::thread& thread : threads) thread.join();

  std::vector<uint32_t> all;
  for (int t = 0; t < kThreads; ++t) {
    EXPECT_EQ(failures[t], 0) << "thread " << t;
    // Each thread sees its own versions grow.
    EXPECT_TRUE(std::is_sorted(versions[t].begin(), versions[t].end())) << "thread " << t;
    all.insert(all.end(), versions[t].begin(), versions[t].end());
  }
  std::sort(all.begin(), all.end());
  ASSERT_EQ(all.size(), static_cast<size_t>(kThreads * kPutsPerThread));
  for (size_t i = 0; i < all.size(); ++i) ASSERT_EQ(all[i], i + 1) << "duplicate or gap";

  absl::StatusOr<StoredMap> latest = repo().GetMap("shared", 0);
  ASSERT_TRUE(latest.ok()) << latest.status();
  EXPECT_EQ(latest->info.version, static_cast<uint32_t>(kThreads * kPutsPerThread));
  for (uint32_t v : {1u, 100u, 200u}) EXPECT_TRUE(repo().GetMap("shared", v).ok()) << v;
}

INSTANTIATE_TEST_SUITE_P(
    AllImplementations, MapRepositoryConformanceTest,
    ::testing::Values(
        Implementation{"Memory", [] { return std::make_unique<MemoryHarness>(); }},
        Implementation{"Sqlite",
                       [] { return std::make_unique<SqlHarness>(testing::Backend::kSqlite); }},
        Implementation{"Postgres",
                       [] { return std::make_unique<SqlHarness>(testing::Backend::kPostgres); }}),
    ImplementationName);

}  // namespace
}  // namespace fleetnav::storage
