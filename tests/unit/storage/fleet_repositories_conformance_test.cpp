// One conformance suite for the marker-set, route, robot, job and token repositories, run over
// the SQL implementation on SQLite (a real file) and on PostgreSQL (a real server), and over the
// in-memory one, so both engines and the fakes used by the layers above behave alike.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <atomic>
#include <memory>
#include <mutex>
#include <set>
#include <thread>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "fleetnav/storage/memory/memory_fleet_repositories.hpp"
#include "fleetnav/storage/sql/sql_fleet_repositories.hpp"
#include "test_database.hpp"

namespace fleetnav::storage {
namespace {

using ::testing::HasSubstr;

using testing::Backend;

class FleetRepositoriesTest : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override {
    if (GetParam() != Backend::kMemory) {
      db_ = std::make_unique<testing::TestDatabase>(GetParam());
      ASSERT_NE(db_->get(), nullptr);
      markers_ = std::make_unique<SqlMarkerSetRepository>(db_->get());
      zones_ = std::make_unique<SqlZoneSetRepository>(db_->get());
      stops_ = std::make_unique<SqlStopRepository>(db_->get());
      routes_ = std::make_unique<SqlRouteRepository>(db_->get());
      robots_ = std::make_unique<SqlRobotRepository>(db_->get());
      jobs_ = std::make_unique<SqlJobRepository>(db_->get());
      tokens_ = std::make_unique<SqlOperatorTokenRepository>(db_->get());
    } else {
      markers_ = std::make_unique<MemoryMarkerSetRepository>();
      zones_ = std::make_unique<MemoryZoneSetRepository>();
      stops_ = std::make_unique<MemoryStopRepository>();
      routes_ = std::make_unique<MemoryRouteRepository>();
      robots_ = std::make_unique<MemoryRobotRepository>();
      jobs_ = std::make_unique<MemoryJobRepository>();
      tokens_ = std::make_unique<MemoryOperatorTokenRepository>();
    }
  }

  static Route StraightRoute(const std::string& name, const std::string& map, double distance) {
    Route route;
    route.name = name;
    route.map_id = map;
    RouteAction action;
    action.params = StraightAction{distance, 0.25};
    route.actions.push_back(action);
    return route;
  }

  static Job QueuedJob(const std::string& key, const std::string& map = "barn") {
    Job job;
    job.route_name = "alley";
    job.route_version = 1;
    job.map_id = map;
    job.idempotency_key = key;
    job.created_unix_ms = job.updated_unix_ms = 1000;
    return job;
  }

  std::unique_ptr<testing::TestDatabase> db_;
  std::unique_ptr<MarkerSetRepository> markers_;
  std::unique_ptr<ZoneSetRepository> zones_;
  std::unique_ptr<StopRepository> stops_;
  std::unique_ptr<RouteRepository> routes_;
  std::unique_ptr<RobotRepository> robots_;
  std::unique_ptr<JobRepository> jobs_;
  std::unique_ptr<OperatorTokenRepository> tokens_;
};

TEST_P(FleetRepositoriesTest, MarkerSetsAreVersionedPerMap) {
  MarkerSet set;
  set.map_id = "barn";
  StripeMarker marker;
  marker.id = 4;
  marker.position_m = {1.0, 4.7};
  marker.yaw_rad = -1.2;
  marker.length_m = 0.6;
  set.markers.push_back(marker);
  EXPECT_EQ(*markers_->PutMarkerSet(set, 10), 1u);
  set.markers[0].length_m = 0.8;
  EXPECT_EQ(*markers_->PutMarkerSet(set, 20), 2u);
  absl::StatusOr<StoredMarkerSet> latest = markers_->GetMarkerSet("barn", 0);
  ASSERT_TRUE(latest.ok());
  EXPECT_EQ(latest->version, 2u);
  EXPECT_NEAR(latest->markers.markers[0].length_m, 0.8, 1e-9);
  EXPECT_NEAR(markers_->GetMarkerSet("barn", 1)->markers.markers[0].yaw_rad, -1.2, 1e-9);
  EXPECT_EQ(markers_->GetMarkerSet("barn", 3).status().code(), absl::StatusCode::kNotFound);
  absl::Status unknown = markers_->GetMarkerSet("shop", 0).status();
  EXPECT_EQ(unknown.code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(unknown.message(), HasSubstr("shop"));
}

TEST_P(FleetRepositoriesTest, RoutesAreVersionedListedAndCountedPerMap) {
  ASSERT_TRUE(routes_->PutRoute(StraightRoute("b-route", "barn", 1.0), 1).ok());
  ASSERT_TRUE(routes_->PutRoute(StraightRoute("a-route", "barn", 2.0), 2).ok());
  EXPECT_EQ(*routes_->PutRoute(StraightRoute("a-route", "barn", 3.0), 3), 2u);
  ASSERT_TRUE(routes_->PutRoute(StraightRoute("shop-route", "shop", 1.0), 4).ok());
  absl::StatusOr<std::vector<StoredRoute>> barn = routes_->ListRoutes("barn");
  ASSERT_TRUE(barn.ok());
  ASSERT_EQ(barn->size(), 2u);
  EXPECT_EQ((*barn)[0].route.name, "a-route");
  EXPECT_EQ((*barn)[0].version, 2u);
  EXPECT_EQ(routes_->ListRoutes("")->size(), 3u);
  EXPECT_EQ(*routes_->CountRoutesOnMap("barn"), 2);
  EXPECT_EQ(*routes_->CountRoutesOnMap("nowhere"), 0);
  absl::StatusOr<StoredRoute> first = routes_->GetRoute("a-route", 1);
  ASSERT_TRUE(first.ok());
  EXPECT_DOUBLE_EQ(std::get<StraightAction>(first->route.actions[0].params).distance_m, 2.0);
  EXPECT_EQ(routes_->GetRoute("c-route", 0).status().code(), absl::StatusCode::kNotFound);
}

TEST_P(FleetRepositoriesTest, ZoneSetsAreVersionedPerMapListedByLatestAndDeletedWhole) {
  ZoneSet barn;
  barn.map_id = "barn";
  barn.zones.push_back({"pen-3", ZoneKind::kNoGo, {{1, 1}, {3, 1}, {3, 2}}, 0.0, 1});
  ZoneSet shop;
  shop.map_id = "shop";
  EXPECT_EQ(*zones_->PutZoneSet(barn, 10), 1u);
  barn.zones.push_back({"kitchen", ZoneKind::kSpeedLimit, {{5, 0}, {8, 0}, {6.5, 2}}, 0.3, 1});
  EXPECT_EQ(*zones_->PutZoneSet(barn, 20), 2u);
  EXPECT_EQ(*zones_->PutZoneSet(shop, 30), 1u);

  absl::StatusOr<StoredZoneSet> latest = zones_->GetZoneSet("barn", 0);
  ASSERT_TRUE(latest.ok()) << latest.status();
  EXPECT_EQ(latest->version, 2u);
  EXPECT_EQ(latest->created_unix_ms, 20);
  EXPECT_EQ(latest->zones.map_id, "barn");
  ASSERT_EQ(latest->zones.zones.size(), 2u);
  EXPECT_DOUBLE_EQ(latest->zones.zones[1].speed_limit_mps, 0.3);
  EXPECT_EQ(zones_->GetZoneSet("barn", 1)->zones.zones.size(), 1u);
  const absl::Status missing_version = zones_->GetZoneSet("barn", 3).status();
  EXPECT_EQ(missing_version.code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(std::string(missing_version.message()), HasSubstr("has no version 3"));
  EXPECT_EQ(zones_->GetZoneSet("yard", 0).status().code(), absl::StatusCode::kNotFound);

  absl::StatusOr<std::vector<StoredZoneSet>> listed = zones_->ListZoneSets();
  ASSERT_TRUE(listed.ok()) << listed.status();
  ASSERT_EQ(listed->size(), 2u);
  EXPECT_EQ((*listed)[0].zones.map_id, "barn");
  EXPECT_EQ((*listed)[0].version, 2u);
  EXPECT_EQ((*listed)[1].zones.map_id, "shop");
  EXPECT_TRUE((*listed)[1].zones.zones.empty());

  ASSERT_TRUE(zones_->DeleteZoneSet("barn").ok());
  EXPECT_EQ(zones_->GetZoneSet("barn", 1).status().code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(zones_->DeleteZoneSet("barn").code(), absl::StatusCode::kNotFound);
  EXPECT_TRUE(zones_->GetZoneSet("shop", 0).ok());
  EXPECT_EQ(*zones_->PutZoneSet(barn, 40), 1u);
}

TEST_P(FleetRepositoriesTest, StopsAreKeptOnePerScopeUntilCleared) {
  RobotStop pen;
  pen.map_id = "barn";
  pen.zone = "pen";
  pen.polygon_in_map = {{1.25, -0.1}, {3, 0.1}, {2.0000000001, 1.7}};
  pen.reason = "cleaning";
  pen.created_unix_ms = 10;
  RobotStop fleet;
  fleet.reason = "inspection";
  fleet.created_unix_ms = 20;
  ASSERT_TRUE(stops_->PutStop(pen).ok());
  ASSERT_TRUE(stops_->PutStop(fleet).ok());
  const absl::Status again = stops_->PutStop(pen);
  EXPECT_EQ(again.code(), absl::StatusCode::kAlreadyExists);
  EXPECT_THAT(std::string(again.message()), HasSubstr("zone 'pen' of map 'barn'"));
  absl::StatusOr<std::vector<RobotStop>> listed = stops_->ListStops();
  ASSERT_TRUE(listed.ok()) << listed.status();
  ASSERT_EQ(listed->size(), 2u);
  EXPECT_EQ((*listed)[0].zone, "pen");
  EXPECT_EQ((*listed)[0].reason, "cleaning");
  ASSERT_EQ((*listed)[0].polygon_in_map.size(), 3u);
  EXPECT_EQ((*listed)[0].polygon_in_map[2], Eigen::Vector2d(2.0000000001, 1.7));  // exactly
  EXPECT_TRUE((*listed)[1].whole_fleet());
  ASSERT_TRUE(stops_->DeleteStop("", "").ok());
  const absl::Status gone = stops_->DeleteStop("", "");
  EXPECT_EQ(gone.code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(std::string(gone.message()), HasSubstr("the whole fleet"));
  EXPECT_EQ(stops_->ListStops()->size(), 1u);
}

TEST_P(FleetRepositoriesTest, ADeletedMarkerSetIsGoneWithEveryVersionOfItsMapOnly) {
  MarkerSet barn;
  barn.map_id = "barn";
  MarkerSet shop;
  shop.map_id = "shop";
  ASSERT_TRUE(markers_->PutMarkerSet(barn, 1).ok());
  ASSERT_TRUE(markers_->PutMarkerSet(barn, 2).ok());
  ASSERT_TRUE(markers_->PutMarkerSet(shop, 3).ok());
  ASSERT_TRUE(markers_->DeleteMarkerSet("barn").ok());
  EXPECT_EQ(markers_->GetMarkerSet("barn", 0).status().code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(markers_->GetMarkerSet("barn", 2).status().code(), absl::StatusCode::kNotFound);
  EXPECT_TRUE(markers_->GetMarkerSet("shop", 0).ok());
  const absl::Status again = markers_->DeleteMarkerSet("barn");
  EXPECT_EQ(again.code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(again.message(), HasSubstr("barn"));
  EXPECT_EQ(*markers_->PutMarkerSet(barn, 4), 1u);
}

TEST_P(FleetRepositoriesTest, ADeletedRouteIsGoneWithEveryVersionAndStartsAgainAtOne) {
  ASSERT_TRUE(routes_->PutRoute(StraightRoute("a-route", "barn", 1.0), 1).ok());
  ASSERT_TRUE(routes_->PutRoute(StraightRoute("a-route", "barn", 2.0), 2).ok());
  ASSERT_TRUE(routes_->PutRoute(StraightRoute("b-route", "barn", 1.0), 3).ok());
  ASSERT_TRUE(routes_->DeleteRoute("a-route").ok());
  EXPECT_EQ(routes_->GetRoute("a-route", 0).status().code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(routes_->GetRoute("a-route", 1).status().code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(*routes_->CountRoutesOnMap("barn"), 1);  // the other route stays
  const absl::Status again = routes_->DeleteRoute("a-route");
  EXPECT_EQ(again.code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(again.message(), HasSubstr("a-route"));
  EXPECT_EQ(*routes_->PutRoute(StraightRoute("a-route", "barn", 4.0), 4), 1u);
}

TEST_P(FleetRepositoriesTest, OperatorTokensAreUniqueByNameAndHashAndListedByName) {
  const std::string hash_a(64, 'a'), hash_b(64, 'b'), hash_c(64, 'c');
  ASSERT_TRUE(tokens_->InsertToken({{"night-shift", Role::kOperator, hash_a}, 10}).ok());
  ASSERT_TRUE(tokens_->InsertToken({{"audit", Role::kViewer, hash_b}, 20}).ok());
  // A taken name, or a taken secret under another name, is refused and changes nothing.
  EXPECT_EQ(tokens_->InsertToken({{"audit", Role::kAdmin, hash_c}, 30}).code(),
            absl::StatusCode::kAlreadyExists);
  EXPECT_EQ(tokens_->InsertToken({{"other", Role::kAdmin, hash_a}, 30}).code(),
            absl::StatusCode::kAlreadyExists);
  absl::StatusOr<std::vector<StoredOperatorToken>> tokens = tokens_->ListTokens();
  ASSERT_TRUE(tokens.ok()) << tokens.status();
  ASSERT_EQ(tokens->size(), 2u);
  EXPECT_EQ((*tokens)[0].token.name, "audit");
  EXPECT_EQ((*tokens)[0].token.role, Role::kViewer);
  EXPECT_EQ((*tokens)[0].created_unix_ms, 20);
  EXPECT_EQ((*tokens)[1].token.name, "night-shift");
  EXPECT_EQ((*tokens)[1].token.role, Role::kOperator);
  EXPECT_EQ((*tokens)[1].token.sha256_hex, hash_a);
  ASSERT_TRUE(tokens_->DeleteToken("audit").ok());
  EXPECT_EQ(tokens_->DeleteToken("audit").code(), absl::StatusCode::kNotFound);
  tokens = tokens_->ListTokens();
  ASSERT_TRUE(tokens.ok());
  ASSERT_EQ(tokens->size(), 1u);
  EXPECT_EQ((*tokens)[0].token.name, "night-shift");
}

TEST_P(FleetRepositoriesTest, RobotsAreUpsertedAndListedById) {
  ASSERT_TRUE(robots_->UpsertRobot({"lely2", "lely-vector", {"straight", "turn"}, "1", 5}).ok());
  ASSERT_TRUE(robots_->UpsertRobot({"lely1", "lely-vector", {}, "1", 6}).ok());
  ASSERT_TRUE(robots_->UpsertRobot({"lely2", "lely-vector", {"straight"}, "2", 7}).ok());
  absl::StatusOr<std::vector<StoredRobot>> robots = robots_->ListRobots();
  ASSERT_TRUE(robots.ok());
  ASSERT_EQ(robots->size(), 2u);
  EXPECT_EQ((*robots)[0].robot_id, "lely1");
  EXPECT_TRUE((*robots)[0].capabilities.empty());
  EXPECT_THAT((*robots)[1].capabilities, ::testing::ElementsAre("straight"));
  EXPECT_EQ((*robots)[1].software_version, "2");
}

TEST_P(FleetRepositoriesTest, JobsGetIdsAreIdempotentOnTheirKeyAndKeepTheirEvents) {
  JobEvent queued;
  queued.type = JobEventType::kQueued;
  absl::StatusOr<CreatedJob> first = jobs_->CreateJob(QueuedJob("k1"), queued);
  ASSERT_TRUE(first.ok());
  EXPECT_EQ(first->job.job_id, "job-000001");
  EXPECT_FALSE(first->deduplicated);
  absl::StatusOr<CreatedJob> again = jobs_->CreateJob(QueuedJob("k1"), queued);
  ASSERT_TRUE(again.ok());
  EXPECT_TRUE(again->deduplicated);
  EXPECT_EQ(again->job.job_id, "job-000001");
  EXPECT_EQ(jobs_->CreateJob(QueuedJob(""), queued)->job.job_id, "job-000002");
  EXPECT_EQ(jobs_->CreateJob(QueuedJob(""), queued)->job.job_id, "job-000003");

  Job job = first->job;
  job.state = JobState::kAssigned;
  job.assigned_robot_id = "lely1";
  JobEvent assigned;
  assigned.type = JobEventType::kAssigned;
  assigned.state = JobState::kAssigned;
  assigned.robot_id = "lely1";
  EXPECT_EQ(*jobs_->UpdateJob(job, assigned), 2);
  EXPECT_EQ(jobs_->GetJob("job-000001")->state, JobState::kAssigned);
  absl::StatusOr<std::vector<JobEvent>> events = jobs_->ListEvents("job-000001", 0);
  ASSERT_TRUE(events.ok());
  ASSERT_EQ(events->size(), 2u);
  EXPECT_EQ((*events)[1].type, JobEventType::kAssigned);
  EXPECT_EQ((*events)[1].robot_id, "lely1");
  EXPECT_EQ(jobs_->ListEvents("job-000001", 1)->size(), 1u);

  Job ghost = job;
  ghost.job_id = "job-999999";
  EXPECT_EQ(jobs_->UpdateJob(ghost, assigned).status().code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(jobs_->GetJob("job-999999").status().code(), absl::StatusCode::kNotFound);
}

TEST_P(FleetRepositoriesTest, ListJobsFiltersAndPagesInCreationOrder) {
  JobEvent queued;
  for (int i = 0; i < 7; ++i) {
    ASSERT_TRUE(jobs_->CreateJob(QueuedJob("", i % 2 ? "shop" : "barn"), queued).ok());
  }
  Job running = *jobs_->GetJob("job-000003");
  running.state = JobState::kRunning;
  running.assigned_robot_id = "lely1";
  ASSERT_TRUE(jobs_->UpdateJob(running, queued).ok());

  JobFilter filter;
  filter.page_size = 3;
  std::vector<std::string> ids;
  do {
    absl::StatusOr<JobPage> page = jobs_->ListJobs(filter);
    ASSERT_TRUE(page.ok());
    EXPECT_LE(page->jobs.size(), 3u);
    for (const Job& j : page->jobs) ids.push_back(j.job_id);
    filter.page_token = page->next_page_token;
  } while (!filter.page_token.empty());
  EXPECT_THAT(ids, ::testing::ElementsAre("job-000001", "job-000002", "job-000003", "job-000004",
                                          "job-000005", "job-000006", "job-000007"));

  const std::map<JobState, int64_t> counts = *jobs_->CountJobsByState();
  EXPECT_EQ(counts, (std::map<JobState, int64_t>{{JobState::kQueued, 6}, {JobState::kRunning, 1}}));

  JobFilter by_state;
  by_state.states = {JobState::kRunning};
  EXPECT_EQ(jobs_->ListJobs(by_state)->jobs.size(), 1u);
  JobFilter by_robot;
  by_robot.robot_id = "lely1";
  EXPECT_EQ(jobs_->ListJobs(by_robot)->jobs[0].job_id, "job-000003");
  JobFilter by_map;
  by_map.map_id = "shop";
  EXPECT_EQ(jobs_->ListJobs(by_map)->jobs.size(), 3u);
  JobFilter bad;
  bad.page_token = "not-a-token";
  EXPECT_EQ(jobs_->ListJobs(bad).status().code(), absl::StatusCode::kInvalidArgument);
}

TEST_P(FleetRepositoriesTest, ConcurrentCreatesGetDistinctConsecutiveJobIdsAndEachItsEvents) {
  // Eight writers at once: on PostgreSQL they race for the next job number on several
  // connections, and the losers run again.
  constexpr int kWriters = 8, kJobsEach = 10;
  std::vector<std::thread> writers;
  std::mutex mutex;
  std::set<std::string> ids;
  std::atomic<int> failures{0};
  for (int w = 0; w < kWriters; ++w) {
    writers.emplace_back([&, w] {
      for (int i = 0; i < kJobsEach; ++i) {
        JobEvent queued;
        queued.type = JobEventType::kQueued;
        absl::StatusOr<CreatedJob> created =
            jobs_->CreateJob(QueuedJob(absl::StrCat("w", w, "-", i)), queued);
        if (!created.ok()) {
          ++failures;
          ADD_FAILURE() << created.status();
          continue;
        }
        std::lock_guard<std::mutex> lock(mutex);
        ids.insert(created->job.job_id);
      }
    });
  }
  for (std::thread& writer : writers) writer.join();
  EXPECT_EQ(failures.load(), 0);
  ASSERT_EQ(ids.size(), static_cast<size_t>(kWriters * kJobsEach));
  EXPECT_EQ(*ids.begin(), "job-000001");
  EXPECT_EQ(*ids.rbegin(), absl::StrFormat("job-%06d", kWriters * kJobsEach));
  for (const std::string& id : ids) {
    absl::StatusOr<std::vector<JobEvent>> events = jobs_->ListEvents(id, 0);
    ASSERT_TRUE(events.ok()) << events.status();
    EXPECT_EQ(events->size(), 1u) << id;
  }
}

INSTANTIATE_TEST_SUITE_P(Repositories, FleetRepositoriesTest,
                         ::testing::Values(Backend::kSqlite, Backend::kPostgres, Backend::kMemory),
                         testing::BackendTestName);

}  // namespace
}  // namespace fleetnav::storage
