// fleetnavd's database refuses what is not its own before writing to it: unrelated SQLite files,
// files that are no database, damaged files, read-only files; and Check() reads without writing.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "fleetnav/storage/sql/sql_map_repository.hpp"
#include "fleetnav/storage/sqlite/schema.hpp"
#include "fleetnav/storage/sqlite/sqlite_database.hpp"
#include "temp_db_path.hpp"

namespace fleetnav::storage {
namespace {

using ::testing::HasSubstr;

std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// Writes a file with plain SQLite (no fleetnav code): `sql` run on a fresh file.
void MakeForeignDatabase(const std::string& path, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  char* error = nullptr;
  ASSERT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error), SQLITE_OK) << error;
  sqlite3_close(db);
}

absl::StatusOr<std::unique_ptr<SqliteDatabase>> OpenFleet(const std::string& path) {
  return SqliteDatabase::Open(path, FleetSchemaMigrations(), FleetDatabaseOptions());
}

TEST(SqliteOwnershipTest, ANewFileIsStampedAndReopens) {
  testing::TempDbPath path;
  ASSERT_TRUE(OpenFleet(path.path()).ok());
  absl::StatusOr<std::unique_ptr<SqliteDatabase>> again = OpenFleet(path.path());
  ASSERT_TRUE(again.ok()) << again.status();
  absl::StatusOr<SqlStatement> id = (*again)->Prepare("PRAGMA application_id");
  ASSERT_TRUE(id.ok());
  ASSERT_TRUE(*id->Step());
  EXPECT_EQ(static_cast<uint32_t>(id->ColumnInt(0)), kFleetApplicationId);
}

TEST(SqliteOwnershipTest, AnUnrelatedSqliteFileIsRefusedAndLeftUntouched) {
  testing::TempDbPath path;
  MakeForeignDatabase(path.path(),
                      "CREATE TABLE people (name TEXT); INSERT INTO people VALUES ('ann');");
  const std::string before = ReadBytes(path.path());
  absl::StatusOr<std::unique_ptr<SqliteDatabase>> db = OpenFleet(path.path());
  ASSERT_FALSE(db.ok());
  EXPECT_EQ(db.status().code(), absl::StatusCode::kFailedPrecondition) << db.status();
  EXPECT_THAT(std::string(db.status().message()), HasSubstr(path.path()));
  EXPECT_THAT(std::string(db.status().message()), HasSubstr("not a fleetnav database"));
  EXPECT_EQ(ReadBytes(path.path()), before);  // no `maps` table, no user_version written
  EXPECT_FALSE(std::filesystem::exists(path.path() + "-wal"));
}

TEST(SqliteOwnershipTest, AFileOfAnotherApplicationIsRefusedEvenWithAMapsTable) {
  testing::TempDbPath path;
  MakeForeignDatabase(path.path(),
                      "PRAGMA application_id=1234; PRAGMA user_version=1; CREATE TABLE maps (x);");
  const std::string before = ReadBytes(path.path());
  absl::StatusOr<std::unique_ptr<SqliteDatabase>> db = OpenFleet(path.path());
  ASSERT_FALSE(db.ok());
  EXPECT_EQ(db.status().code(), absl::StatusCode::kFailedPrecondition) << db.status();
  EXPECT_THAT(std::string(db.status().message()), HasSubstr("application_id 0x000004d2"));
  EXPECT_EQ(ReadBytes(path.path()), before);
}

TEST(SqliteOwnershipTest, AFileThatIsNoDatabaseIsDataLossNamingTheFile) {
  testing::TempDbPath path;
  {
    std::ofstream out(path.path(), std::ios::binary);
    for (int i = 0; i < 200; ++i) out << "these are an operator's notes, not a database\n";
  }
  const std::string before = ReadBytes(path.path());
  absl::StatusOr<std::unique_ptr<SqliteDatabase>> db = OpenFleet(path.path());
  ASSERT_FALSE(db.ok());
  EXPECT_EQ(db.status().code(), absl::StatusCode::kDataLoss) << db.status();
  EXPECT_THAT(std::string(db.status().message()), HasSubstr(path.path()));
  EXPECT_EQ(ReadBytes(path.path()), before);
}

TEST(SqliteOwnershipTest, AnUnstampedFleetDatabaseFromBeforeIdsIsTakenAndStamped) {
  testing::TempDbPath path;
  {
    // What earlier fleetnavd versions wrote: the schema, no application_id.
    absl::StatusOr<std::unique_ptr<SqliteDatabase>> old =
        SqliteDatabase::Open(path.path(), FleetSchemaMigrations());
    ASSERT_TRUE(old.ok()) << old.status();
  }
  absl::StatusOr<std::unique_ptr<SqliteDatabase>> db = OpenFleet(path.path());
  ASSERT_TRUE(db.ok()) << db.status();
  absl::StatusOr<SqlStatement> id = (*db)->Prepare("PRAGMA application_id");
  ASSERT_TRUE(id.ok());
  ASSERT_TRUE(*id->Step());
  EXPECT_EQ(static_cast<uint32_t>(id->ColumnInt(0)), kFleetApplicationId);
}

/// A fleet database with enough maps to span many pages, closed (WAL checkpointed).
void MakeFleetDatabaseWithMaps(const std::string& path) {
  absl::StatusOr<std::unique_ptr<SqliteDatabase>> db = OpenFleet(path);
  ASSERT_TRUE(db.ok()) << db.status();
  SqlMapRepository maps(db->get());
  std::vector<int8_t> cells(200 * 200, 0);
  for (int i = 0; i < 8; ++i) {
    absl::StatusOr<OccupancyGrid> grid = OccupancyGrid::Create(200, 200, 0.05, Pose2(), cells);
    ASSERT_TRUE(grid.ok());
    ASSERT_TRUE(maps.PutMap("map" + std::to_string(i), *grid, "", 0).ok());
  }
}

TEST(SqliteOwnershipTest, OverwrittenPagesAreDataLossAtStartAndInCheck) {
  testing::TempDbPath path;
  MakeFleetDatabaseWithMaps(path.path());
  const std::string intact = ReadBytes(path.path());
  ASSERT_GT(intact.size(), 16u * 4096u);
  {
    // Overwrite pages 2-5 (the tables' b-tree roots and first leaves) with a pattern.
    std::fstream file(path.path(), std::ios::binary | std::ios::in | std::ios::out);
    file.seekp(4096);
    const std::string garbage(4 * 4096, '\x5a');
    file.write(garbage.data(), static_cast<std::streamsize>(garbage.size()));
  }
  absl::StatusOr<std::unique_ptr<SqliteDatabase>> db = OpenFleet(path.path());
  ASSERT_FALSE(db.ok());
  EXPECT_EQ(db.status().code(), absl::StatusCode::kDataLoss) << db.status();
  EXPECT_THAT(std::string(db.status().message()), HasSubstr(path.path()));

  absl::StatusOr<SqliteCheckReport> report =
      SqliteDatabase::Check(path.path(), FleetDatabaseOptions());
  if (report.ok()) {
    EXPECT_FALSE(report->ok());
  } else {
    EXPECT_EQ(report.status().code(), absl::StatusCode::kDataLoss) << report.status();
  }
}

TEST(SqliteOwnershipTest, CheckReadsAnIntactFileWithoutWritingIt) {
  testing::TempDbPath path;
  MakeFleetDatabaseWithMaps(path.path());
  const std::string before = ReadBytes(path.path());
  absl::StatusOr<SqliteCheckReport> report =
      SqliteDatabase::Check(path.path(), FleetDatabaseOptions());
  ASSERT_TRUE(report.ok()) << report.status();
  EXPECT_TRUE(report->ok()) << report->problems.front();
  EXPECT_EQ(report->schema_version, static_cast<int>(FleetSchemaMigrations().size()));
  EXPECT_EQ(ReadBytes(path.path()), before);
}

TEST(SqliteOwnershipTest, CheckReportsAForeignFileAsAProblem) {
  testing::TempDbPath path;
  MakeForeignDatabase(path.path(), "CREATE TABLE people (name TEXT);");
  absl::StatusOr<SqliteCheckReport> report =
      SqliteDatabase::Check(path.path(), FleetDatabaseOptions());
  ASSERT_TRUE(report.ok()) << report.status();
  ASSERT_EQ(report->problems.size(), 1u);
  EXPECT_THAT(report->problems[0], HasSubstr("not a fleetnav database"));
}

TEST(SqliteOwnershipTest, AReadOnlyFileIsRefusedAtOpenNamingTheFile) {
  testing::TempDbPath path;
  MakeFleetDatabaseWithMaps(path.path());
  ASSERT_EQ(::chmod(path.path().c_str(), 0444), 0);
  // Root may write any file, so the open runs as an unprivileged user when the test is root.
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    if (::geteuid() == 0 && (::setgid(65534) != 0 || ::setuid(65534) != 0)) ::_exit(3);
    absl::StatusOr<std::unique_ptr<SqliteDatabase>> db = OpenFleet(path.path());
    const bool refused = !db.ok() && db.status().code() == absl::StatusCode::kFailedPrecondition &&
                         db.status().message().find("read-only") != std::string::npos &&
                         db.status().message().find(path.path()) != std::string::npos;
    ::_exit(refused ? 0 : 1);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "3: could not drop privileges; 1: the file was accepted "
                                       "or refused for another reason";
}

}  // namespace
}  // namespace fleetnav::storage
