// SQLite-only behaviour: durability across reopen, migrations by user_version, WAL, and
// transaction rollback.
#include "fleetnav/storage/sqlite/sqlite_database.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "fleetnav/storage/sql/sql_map_repository.hpp"
#include "fleetnav/storage/sqlite/schema.hpp"
#include "temp_db_path.hpp"

namespace fleetnav::storage {
namespace {

using ::testing::HasSubstr;

std::unique_ptr<SqliteDatabase> OpenOrDie(const std::string& path,
                                          const std::vector<std::string>& migrations) {
  absl::StatusOr<std::unique_ptr<SqliteDatabase>> db = SqliteDatabase::Open(path, migrations);
  EXPECT_TRUE(db.ok()) << db.status();
  return db.ok() ? *std::move(db) : nullptr;
}

int64_t QueryInt(SqliteDatabase& db, const std::string& sql) {
  absl::StatusOr<SqlStatement> stmt = db.Prepare(sql);
  EXPECT_TRUE(stmt.ok()) << stmt.status();
  if (!stmt.ok()) return -1;
  absl::StatusOr<bool> row = stmt->Step();
  EXPECT_TRUE(row.ok() && *row) << sql;
  return (row.ok() && *row) ? stmt->ColumnInt(0) : -1;
}

std::string QueryText(SqliteDatabase& db, const std::string& sql) {
  absl::StatusOr<SqlStatement> stmt = db.Prepare(sql);
  EXPECT_TRUE(stmt.ok()) << stmt.status();
  if (!stmt.ok()) return "";
  absl::StatusOr<bool> row = stmt->Step();
  EXPECT_TRUE(row.ok() && *row) << sql;
  return (row.ok() && *row) ? stmt->ColumnText(0) : "";
}

OccupancyGrid SampleGrid() {
  absl::StatusOr<OccupancyGrid> grid =
      OccupancyGrid::Create(3, 2, 0.05, Pose2(1.5, -0.5, 0.75), {0, 100, -1, 50, 0, 100});
  EXPECT_TRUE(grid.ok()) << grid.status();
  return *std::move(grid);
}

TEST(SqliteDatabaseTest, DataSurvivesClosingAndReopening) {
  testing::TempDbPath path;
  const OccupancyGrid grid = SampleGrid();
  {
    std::unique_ptr<SqliteDatabase> db = OpenOrDie(path.path(), FleetSchemaMigrations());
    ASSERT_NE(db, nullptr);
    SqlMapRepository repo(db.get());
    ASSERT_TRUE(repo.PutMap("barn", grid, "first", 11).ok());
    ASSERT_TRUE(repo.PutMap("barn", grid, "second", 22).ok());
  }
  ASSERT_TRUE(std::filesystem::exists(path.path()));
  std::unique_ptr<SqliteDatabase> db = OpenOrDie(path.path(), FleetSchemaMigrations());
  ASSERT_NE(db, nullptr);
  SqlMapRepository repo(db.get());
  absl::StatusOr<StoredMap> got = repo.GetMap("barn", 0);
  ASSERT_TRUE(got.ok()) << got.status();
  EXPECT_EQ(got->info.version, 2u);
  EXPECT_EQ(got->info.description, "second");
  EXPECT_EQ(got->info.created_unix_ms, 22);
  EXPECT_EQ(got->grid, grid);
  // Versions continue after the reopen.
  absl::StatusOr<MapInfo> third = repo.PutMap("barn", grid, "third", 33);
  ASSERT_TRUE(third.ok()) << third.status();
  EXPECT_EQ(third->version, 3u);
}

TEST(SqliteDatabaseTest, UserVersionEqualsTheNumberOfMigrationsAfterOpen) {
  testing::TempDbPath path;
  std::unique_ptr<SqliteDatabase> db = OpenOrDie(path.path(), FleetSchemaMigrations());
  ASSERT_NE(db, nullptr);
  const int expected = static_cast<int>(FleetSchemaMigrations().size());
  ASSERT_GE(expected, 1);
  EXPECT_EQ(db->user_version(), expected);
  EXPECT_EQ(QueryInt(*db, "PRAGMA user_version"), expected);
  EXPECT_EQ(QueryInt(*db,
                     "SELECT COUNT(*) FROM sqlite_master WHERE type = 'table' AND "
                     "name = 'maps'"),
            1);
}

TEST(SqliteDatabaseTest, ReopeningDoesNotRerunMigrations) {
  testing::TempDbPath path;
  ASSERT_NE(OpenOrDie(path.path(), FleetSchemaMigrations()), nullptr);
  // Migration 1 creates a table without IF NOT EXISTS: running it twice would fail.
  std::unique_ptr<SqliteDatabase> db = OpenOrDie(path.path(), FleetSchemaMigrations());
  ASSERT_NE(db, nullptr);
  EXPECT_EQ(db->user_version(), static_cast<int>(FleetSchemaMigrations().size()));
}

TEST(SqliteDatabaseTest, AppliesOnlyTheNewMigrationsInOrder) {
  testing::TempDbPath path;
  std::vector<std::string> migrations = {"CREATE TABLE a (x INTEGER)"};
  {
    std::unique_ptr<SqliteDatabase> db = OpenOrDie(path.path(), migrations);
    ASSERT_NE(db, nullptr);
    EXPECT_EQ(db->user_version(), 1);
  }
  migrations.push_back("INSERT INTO a (x) VALUES (7)");
  migrations.push_back("CREATE TABLE b (y INTEGER)");
  std::unique_ptr<SqliteDatabase> db = OpenOrDie(path.path(), migrations);
  ASSERT_NE(db, nullptr);
  EXPECT_EQ(db->user_version(), 3);
  EXPECT_EQ(QueryInt(*db, "SELECT COUNT(*) FROM a"), 1);
  EXPECT_EQ(QueryInt(*db, "SELECT COUNT(*) FROM b"), 0);
}

TEST(SqliteDatabaseTest, FailedMigrationLeavesTheVersionBeforeIt) {
  testing::TempDbPath path;
  const std::vector<std::string> migrations = {"CREATE TABLE a (x INTEGER)",
                                               "CREATE TABLE b (y INTEGER); NOT VALID SQL"};
  absl::StatusOr<std::unique_ptr<SqliteDatabase>> failed =
      SqliteDatabase::Open(path.path(), migrations);
  ASSERT_FALSE(failed.ok());

  std::unique_ptr<SqliteDatabase> db = OpenOrDie(path.path(), {migrations[0]});
  ASSERT_NE(db, nullptr);
  EXPECT_EQ(db->user_version(), 1);
  // Migration 2 rolled back as a whole: table b was not left behind.
  EXPECT_EQ(QueryInt(*db, "SELECT COUNT(*) FROM sqlite_master WHERE name = 'b'"), 0);
}

TEST(SqliteDatabaseTest, NewerSchemaThanTheBinaryIsFailedPrecondition) {
  testing::TempDbPath path;
  const int newer = static_cast<int>(FleetSchemaMigrations().size()) + 1;
  {
    std::unique_ptr<SqliteDatabase> db = OpenOrDie(path.path(), {});
    ASSERT_NE(db, nullptr);
    ASSERT_TRUE(db->Execute("PRAGMA user_version=" + std::to_string(newer)).ok());
  }
  absl::StatusOr<std::unique_ptr<SqliteDatabase>> db =
      SqliteDatabase::Open(path.path(), FleetSchemaMigrations());
  ASSERT_FALSE(db.ok());
  EXPECT_EQ(db.status().code(), absl::StatusCode::kFailedPrecondition) << db.status();
  EXPECT_THAT(std::string(db.status().message()), HasSubstr(std::to_string(newer)));
}

TEST(SqliteDatabaseTest, JournalModeIsWal) {
  testing::TempDbPath path;
  std::unique_ptr<SqliteDatabase> db = OpenOrDie(path.path(), FleetSchemaMigrations());
  ASSERT_NE(db, nullptr);
  EXPECT_EQ(QueryText(*db, "PRAGMA journal_mode"), "wal");
  EXPECT_EQ(QueryInt(*db, "PRAGMA foreign_keys"), 1);
  EXPECT_EQ(QueryInt(*db, "PRAGMA synchronous"), 2);  // FULL
}

TEST(SqliteDatabaseTest, NormalDurabilityUsesSynchronousNormal) {
  testing::TempDbPath path;
  absl::StatusOr<std::unique_ptr<SqliteDatabase>> db = SqliteDatabase::Open(
      path.path(), FleetSchemaMigrations(), FleetDatabaseOptions(Durability::kNormal));
  ASSERT_TRUE(db.ok()) << db.status();
  EXPECT_EQ(QueryInt(**db, "PRAGMA synchronous"), 1);  // NORMAL
  EXPECT_EQ(QueryText(**db, "PRAGMA journal_mode"), "wal");
}

TEST(SqliteDatabaseTest, TransactionWhoseBodyFailsRollsBack) {
  testing::TempDbPath path;
  std::unique_ptr<SqliteDatabase> db = OpenOrDie(path.path(), FleetSchemaMigrations());
  ASSERT_NE(db, nullptr);
  const absl::Status status = db->Transaction([&]() -> absl::Status {
    absl::StatusOr<SqlStatement> insert = db->Prepare(
        "INSERT INTO maps (map_id, version, width, height, resolution_m, origin_x_m, "
        "origin_y_m, origin_yaw_rad, cells, created_unix_ms) "
        "VALUES ('barn', 1, 1, 1, 0.05, 0, 0, 0, x'00', 0)");
    if (!insert.ok()) return insert.status();
    if (absl::Status run = insert->Run(); !run.ok()) return run;
    // The row is visible inside the transaction ...
    EXPECT_EQ(QueryInt(*db, "SELECT COUNT(*) FROM maps"), 1);
    return absl::AbortedError("body gave up");
  });
  // ... the body's error comes back unchanged, and nothing was stored.
  EXPECT_EQ(status.code(), absl::StatusCode::kAborted);
  EXPECT_EQ(status.message(), "body gave up");
  EXPECT_EQ(QueryInt(*db, "SELECT COUNT(*) FROM maps"), 0);
  SqlMapRepository repo(db.get());
  EXPECT_EQ(repo.GetMap("barn", 0).status().code(), absl::StatusCode::kNotFound);

  // The connection is usable afterwards and a successful body commits.
  ASSERT_TRUE(db->Transaction([&] {
                  return db->Execute(
                      "INSERT INTO maps (map_id, version, width, height, resolution_m, "
                      "origin_x_m, origin_y_m, origin_yaw_rad, cells, created_unix_ms) "
                      "VALUES ('barn', 1, 1, 1, 0.05, 0, 0, 0, x'00', 0)");
                }).ok());
  EXPECT_EQ(QueryInt(*db, "SELECT COUNT(*) FROM maps"), 1);
}

TEST(SqliteDatabaseTest, DuplicatePrimaryKeyIsFailedPreconditionAndStoresNothing) {
  testing::TempDbPath path;
  std::unique_ptr<SqliteDatabase> db = OpenOrDie(path.path(), FleetSchemaMigrations());
  ASSERT_NE(db, nullptr);
  const std::string insert =
      "INSERT INTO maps (map_id, version, width, height, resolution_m, origin_x_m, origin_y_m, "
      "origin_yaw_rad, cells, created_unix_ms) VALUES ('barn', 1, 1, 1, 0.05, 0, 0, 0, x'00', 0)";
  const absl::Status status = db->Transaction([&]() -> absl::Status {
    if (absl::Status s = db->Execute(insert); !s.ok()) return s;
    return db->Execute(insert);
  });
  EXPECT_EQ(status.code(), absl::StatusCode::kFailedPrecondition) << status;
  EXPECT_EQ(QueryInt(*db, "SELECT COUNT(*) FROM maps"), 0);
}

TEST(SqliteDatabaseTest, BadSqlIsAnErrorNotACrash) {
  testing::TempDbPath path;
  std::unique_ptr<SqliteDatabase> db = OpenOrDie(path.path(), FleetSchemaMigrations());
  ASSERT_NE(db, nullptr);
  const absl::StatusOr<SqlStatement> stmt = db->Prepare("SELEKT nothing");
  EXPECT_FALSE(stmt.ok());
  EXPECT_FALSE(db->Execute("DROP TABLE no_such_table").ok());
}

TEST(SqliteDatabaseTest, CannotOpenInAMissingDirectory) {
  const std::string path = (std::filesystem::path(::testing::TempDir()) /
                            "fleetnav_storage_no_such_dir_8c1f" / "sub" / "fleet.db")
                               .string();
  ASSERT_FALSE(std::filesystem::exists(std::filesystem::path(path).parent_path()));
  absl::StatusOr<std::unique_ptr<SqliteDatabase>> db =
      SqliteDatabase::Open(path, FleetSchemaMigrations());
  ASSERT_FALSE(db.ok());
  EXPECT_EQ(db.status().code(), absl::StatusCode::kUnavailable) << db.status();
  EXPECT_THAT(std::string(db.status().message()), HasSubstr(path));
}

}  // namespace
}  // namespace fleetnav::storage
