// PostgreSQL-only behaviour on a real server: the schema table and its versions, refusing
// databases that are not fleetnav's, migrating once when replicas start together, and what a
// server that cannot be reached or goes away mid-run does to transactions.
#include "fleetnav/storage/postgres/pg_database.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <thread>

#include "absl/strings/str_cat.h"
#include "fleetnav/storage/postgres/pg_schema.hpp"
#include "fleetnav/storage/sql/sql_fleet_repositories.hpp"
#include "fleetnav/storage/sqlite/schema.hpp"
#include "postgres_server.hpp"

namespace fleetnav::storage {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

/// A new empty database on the process's server.
std::string NewDatabase() {
  absl::StatusOr<std::string> uri = fleetnav::testing::NewSharedDatabase("pg");
  EXPECT_TRUE(uri.ok()) << uri.status();
  return uri.value_or("");
}

int64_t CountRows(PgDatabase& db, const std::string& sql) {
  int64_t count = -1;
  EXPECT_TRUE(db.Transaction([&]() -> absl::Status {
                  absl::StatusOr<SqlStatement> query = db.Prepare(sql);
                  if (!query.ok()) return query.status();
                  absl::StatusOr<bool> row = query->Step();
                  if (!row.ok()) return row.status();
                  count = query->ColumnInt(0);
                  return absl::OkStatus();
                }).ok());
  return count;
}

TEST(PgDatabaseTest, BothEnginesHaveTheSameSchemaVersions) {
  EXPECT_EQ(PostgresFleetSchemaMigrations().size(), FleetSchemaMigrations().size());
}

TEST(PgDatabaseTest, ANewDatabaseIsStampedAndMigratedToTheLatestVersion) {
  const std::string uri = NewDatabase();
  absl::StatusOr<std::unique_ptr<PgDatabase>> db =
      PgDatabase::Open(uri, PostgresFleetSchemaMigrations());
  ASSERT_TRUE(db.ok()) << db.status();
  EXPECT_EQ((*db)->schema_version(), static_cast<int>(PostgresFleetSchemaMigrations().size()));
  EXPECT_EQ(CountRows(**db,
                      "SELECT COUNT(*) FROM fleetnav_schema WHERE application = "
                      "'fleetnav'"),
            1);
  EXPECT_THAT((*db)->Describe(), HasSubstr("PostgreSQL database pg_"));
  // Opened again: nothing to migrate, same version.
  db->reset();
  db = PgDatabase::Open(uri, PostgresFleetSchemaMigrations());
  ASSERT_TRUE(db.ok()) << db.status();
  EXPECT_EQ((*db)->schema_version(), static_cast<int>(PostgresFleetSchemaMigrations().size()));
}

TEST(PgDatabaseTest, AnOlderSchemaIsMigratedKeepingItsRows) {
  const std::string uri = NewDatabase();
  std::vector<std::string> first_two(PostgresFleetSchemaMigrations().begin(),
                                     PostgresFleetSchemaMigrations().begin() + 2);
  {
    absl::StatusOr<std::unique_ptr<PgDatabase>> db = PgDatabase::Open(uri, first_two);
    ASSERT_TRUE(db.ok()) << db.status();
    SqlRobotRepository robots(db->get());
    ASSERT_TRUE(robots.UpsertRobot({"lely1", "lely-vector", {"straight"}, "1", 7}).ok());
  }
  absl::StatusOr<std::unique_ptr<PgDatabase>> db =
      PgDatabase::Open(uri, PostgresFleetSchemaMigrations());
  ASSERT_TRUE(db.ok()) << db.status();
  SqlRobotRepository robots(db->get());
  absl::StatusOr<std::vector<StoredRobot>> listed = robots.ListRobots();
  ASSERT_TRUE(listed.ok());
  ASSERT_EQ(listed->size(), 1u);
  SqlOperatorTokenRepository tokens(db->get());  // a table of migration 4
  EXPECT_TRUE(tokens.ListTokens().ok());
}

// Migration 5 numbers jobs from a sequence: it starts after the jobs a database already holds.
TEST(PgDatabaseTest, JobNumbersGoOnAfterTheJobsOfAMigratedDatabase) {
  const std::string uri = NewDatabase();
  std::vector<std::string> first_four(PostgresFleetSchemaMigrations().begin(),
                                      PostgresFleetSchemaMigrations().begin() + 4);
  {
    absl::StatusOr<std::unique_ptr<PgDatabase>> db = PgDatabase::Open(uri, first_four);
    ASSERT_TRUE(db.ok()) << db.status();
    ASSERT_TRUE((*db)
                    ->Transaction([&]() -> absl::Status {
                      absl::StatusOr<SqlStatement> insert = (*db)->Prepare(
                          "INSERT INTO jobs VALUES (41, 'job-000041', 0, 'r', 1, 'm', 0, 0, 0, 0, "
                          "'', '', 0, NULL, 0, 0, 0, 0, '')");
                      if (!insert.ok()) return insert.status();
                      return insert->Run();
                    })
                    .ok());
  }
  absl::StatusOr<std::unique_ptr<PgDatabase>> db =
      PgDatabase::Open(uri, PostgresFleetSchemaMigrations());
  ASSERT_TRUE(db.ok()) << db.status();
  SqlJobRepository jobs(db->get());
  Job job;
  job.route_name = "r";
  job.map_id = "m";
  absl::StatusOr<CreatedJob> created = jobs.CreateJob(job, JobEvent{});
  ASSERT_TRUE(created.ok()) << created.status();
  EXPECT_EQ(created->job.job_id, "job-000042");
}

TEST(PgDatabaseTest, ANewerSchemaIsRefusedNamingBothVersions) {
  const std::string uri = NewDatabase();
  ASSERT_TRUE(PgDatabase::Open(uri, PostgresFleetSchemaMigrations()).ok());
  std::vector<std::string> older(PostgresFleetSchemaMigrations().begin(),
                                 PostgresFleetSchemaMigrations().begin() + 3);
  const absl::Status refused = PgDatabase::Open(uri, older).status();
  EXPECT_EQ(refused.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_THAT(refused.message(),
              HasSubstr(absl::StrCat("schema version ", PostgresFleetSchemaMigrations().size(),
                                     " is newer than this binary's 3")));
}

TEST(PgDatabaseTest, ADatabaseOfAnotherApplicationIsRefusedAndLeftUntouched) {
  const std::string uri = NewDatabase();
  {
    absl::StatusOr<std::unique_ptr<PgDatabase>> other =
        PgDatabase::Open(uri, {"CREATE TABLE people (name TEXT)"}, {.application = "payroll"});
    ASSERT_TRUE(other.ok()) << other.status();
  }
  const absl::Status refused = PgDatabase::Open(uri, PostgresFleetSchemaMigrations()).status();
  EXPECT_EQ(refused.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_THAT(refused.message(), HasSubstr("belongs to 'payroll'"));
  // Tables without any schema table: refused too, and no schema table is made.
  const std::string bare = NewDatabase();
  {
    absl::StatusOr<std::unique_ptr<PgDatabase>> setup =
        PgDatabase::Open(bare, {"CREATE TABLE people (name TEXT)"});
    ASSERT_TRUE(setup.ok());
    ASSERT_TRUE((*setup)
                    ->Transaction([&]() -> absl::Status {
                      absl::StatusOr<SqlStatement> drop =
                          (*setup)->Prepare("DROP TABLE fleetnav_schema");
                      return drop.ok() ? drop->Run() : drop.status();
                    })
                    .ok());
  }
  const absl::Status foreign = PgDatabase::Open(bare, PostgresFleetSchemaMigrations()).status();
  EXPECT_EQ(foreign.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_THAT(foreign.message(), HasSubstr("not a fleetnav database"));
}

TEST(PgDatabaseTest, ReplicasStartingTogetherMigrateOnce) {
  const std::string uri = NewDatabase();
  std::vector<std::thread> replicas;
  std::atomic<int> opened{0};
  for (int i = 0; i < 4; ++i) {
    replicas.emplace_back([&] {
      absl::StatusOr<std::unique_ptr<PgDatabase>> db =
          PgDatabase::Open(uri, PostgresFleetSchemaMigrations());
      EXPECT_TRUE(db.ok()) << db.status();
      opened += db.ok();
    });
  }
  for (std::thread& replica : replicas) replica.join();
  EXPECT_EQ(opened.load(), 4);
  absl::StatusOr<std::unique_ptr<PgDatabase>> db =
      PgDatabase::Open(uri, PostgresFleetSchemaMigrations());
  ASSERT_TRUE(db.ok());
  EXPECT_EQ(CountRows(**db, "SELECT COUNT(*) FROM fleetnav_schema"), 1);
}

TEST(PgDatabaseTest, AnUnreachableServerIsUnavailableWithoutThePassword) {
  const absl::Status status =
      PgDatabase::Open("postgresql://fleetnav:s3cret-pw@127.0.0.1:1/fleet",
                       PostgresFleetSchemaMigrations(), {.connect_wait_s = 0.3})
          .status();
  EXPECT_EQ(status.code(), absl::StatusCode::kUnavailable);
  EXPECT_THAT(status.message(), HasSubstr("cannot reach PostgreSQL within 0.3 s"));
  EXPECT_THAT(status.message(), Not(HasSubstr("s3cret-pw")));
}

TEST(PgDatabaseTest, AServerThatGoesAwayFailsTransactionsUntilItIsBackWithNothingHalfWritten) {
  absl::StatusOr<std::unique_ptr<fleetnav::testing::TemporaryPostgres>> server =
      fleetnav::testing::TemporaryPostgres::Start();
  ASSERT_TRUE(server.ok()) << server.status();
  absl::StatusOr<std::string> uri = (*server)->CreateDatabase("fleet");
  ASSERT_TRUE(uri.ok()) << uri.status();
  absl::StatusOr<std::unique_ptr<PgDatabase>> db =
      PgDatabase::Open(*uri, PostgresFleetSchemaMigrations(), {.reconnect_wait_s = 0.3});
  ASSERT_TRUE(db.ok()) << db.status();
  SqlRobotRepository robots(db->get());
  ASSERT_TRUE(robots.UpsertRobot({"lely1", "lely-vector", {}, "1", 1}).ok());

  ASSERT_TRUE((*server)->Kill().ok());
  const absl::Status lost = robots.UpsertRobot({"lely2", "lely-vector", {}, "1", 2});
  EXPECT_EQ(lost.code(), absl::StatusCode::kUnavailable) << lost;
  // While it is away, every transaction says so (after a short reconnection attempt).
  EXPECT_EQ(robots.ListRobots().status().code(), absl::StatusCode::kUnavailable);

  ASSERT_TRUE((*server)->Restart().ok());
  absl::StatusOr<std::vector<StoredRobot>> listed = robots.ListRobots();
  ASSERT_TRUE(listed.ok()) << listed.status();
  ASSERT_EQ(listed->size(), 1u);  // lely2's write failed as a whole
  EXPECT_EQ((*listed)[0].robot_id, "lely1");
  EXPECT_TRUE(robots.UpsertRobot({"lely2", "lely-vector", {}, "1", 3}).ok());
}

}  // namespace
}  // namespace fleetnav::storage
