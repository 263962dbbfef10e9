// fleetnavd refuses a database file that is not its own, damaged or unreadable at start, naming
// the file and writing nothing (and a PostgreSQL server it cannot reach, without its password);
// `fleetnavd --check-db` reports on a file without writing to it.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fleetnav/scenario/child_process.hpp"
#include "fleetnav/storage/sqlite/schema.hpp"
#include "fleetnav/storage/sqlite/sqlite_database.hpp"

namespace fleetnav {
namespace {

using scenario::ChildProcess;
using ::testing::HasSubstr;

std::string TempPath(const std::string& name) {
  const std::string path = (std::filesystem::path(::testing::TempDir()) /
                            ("dbfile-" + std::to_string(getpid()) + "-" + name))
                               .string();
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path + suffix);
  return path;
}

std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

struct RunResult {
  int exit_code = -1;
  std::string out;
};

RunResult RunFleetnavd(const std::vector<std::string>& args, const std::string& name) {
  std::vector<std::string> argv = {FLEETNAV_FLEETNAVD_PATH, "--insecure"};
  argv.insert(argv.end(), args.begin(), args.end());
  ChildProcess child(argv, TempPath(name + ".out"), TempPath(name + ".err"));
  const std::optional<int> code = child.Wait(30.0);
  RunResult run;
  run.exit_code = code.value_or(-1);
  run.out = child.Stdout() + child.Stderr();
  if (!code) child.Stop();
  return run;
}

void MakeFleetDatabase(const std::string& path) {
  absl::StatusOr<std::unique_ptr<storage::SqliteDatabase>> db = storage::SqliteDatabase::Open(
      path, storage::FleetSchemaMigrations(), storage::FleetDatabaseOptions());
  ASSERT_TRUE(db.ok()) << db.status();
}

TEST(FleetnavdDatabaseTest, AnUnrelatedSqliteFileIsRefusedAtStartAndLeftUntouched) {
  const std::string path = TempPath("people.db");
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, "CREATE TABLE people (name TEXT)", nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  const std::string before = ReadBytes(path);
  const RunResult run = RunFleetnavd({"--db", path, "--listen", "127.0.0.1:0"}, "foreign");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_THAT(run.out, HasSubstr("database '" + path + "'"));
  EXPECT_THAT(run.out, HasSubstr("not a fleetnav database"));
  EXPECT_EQ(ReadBytes(path), before);
}

TEST(FleetnavdDatabaseTest, CheckDbSaysOkForASoundFileAndWritesNothing) {
  const std::string path = TempPath("sound.db");
  MakeFleetDatabase(path);
  const std::string before = ReadBytes(path);
  const RunResult run = RunFleetnavd({"--check-db", "--db", path}, "check-ok");
  EXPECT_EQ(run.exit_code, 0) << run.out;
  EXPECT_THAT(run.out, HasSubstr("schema version"));
  EXPECT_THAT(run.out, HasSubstr("\nok\n"));
  EXPECT_EQ(ReadBytes(path), before);
}

TEST(FleetnavdDatabaseTest, CheckDbFindsOverwrittenPagesAndTheServerRefusesTheFile) {
  const std::string path = TempPath("damaged.db");
  {
    absl::StatusOr<std::unique_ptr<storage::SqliteDatabase>> db = storage::SqliteDatabase::Open(
        path, storage::FleetSchemaMigrations(), storage::FleetDatabaseOptions());
    ASSERT_TRUE(db.ok()) << db.status();
    // Enough rows to fill several pages of the marker-set table.
    ASSERT_TRUE((*db)
                    ->Execute("WITH RECURSIVE n(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM n "
                              "WHERE i < 400) INSERT INTO marker_sets SELECT 'm' || i, 1, "
                              "printf('%.200c', 'x'), 0 FROM n")
                    .ok());
  }
  {
    std::fstream file(path, std::ios::binary | std::ios::in | std::ios::out);
    file.seekp(4096);
    const std::string garbage(3 * 4096, '\x5a');
    file.write(garbage.data(), static_cast<std::streamsize>(garbage.size()));
  }
  const RunResult check = RunFleetnavd({"--check-db", "--db", path}, "check-damaged");
  EXPECT_NE(check.exit_code, 0) << check.out;
  EXPECT_THAT(check.out, HasSubstr(path));

  const RunResult serve = RunFleetnavd({"--db", path, "--listen", "127.0.0.1:0"}, "serve-damaged");
  EXPECT_NE(serve.exit_code, 0) << serve.out;
  EXPECT_THAT(serve.out, HasSubstr("database '" + path + "'"));
  EXPECT_THAT(serve.out, HasSubstr("damaged"));
}

TEST(FleetnavdDatabaseTest, CheckDbOfAMissingFileExits2NamingIt) {
  const std::string path = TempPath("missing.db");
  const RunResult run = RunFleetnavd({"--check-db", "--db", path}, "check-missing");
  EXPECT_EQ(run.exit_code, 2) << run.out;
  EXPECT_THAT(run.out, HasSubstr(path));
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(FleetnavdDatabaseTest, AnUnreachablePostgresIsNamedWithoutItsPasswordAndTheServerExits1) {
  const RunResult run = RunFleetnavd({"--db", "postgresql://fleetnav:hunter2@127.0.0.1:1/fleet",
                                      "--db-wait-s", "0.5", "--listen", "127.0.0.1:0"},
                                     "pg-unreachable");
  EXPECT_EQ(run.exit_code, 1) << run.out;
  EXPECT_THAT(run.out, HasSubstr("cannot reach PostgreSQL within 0.5 s"));
  EXPECT_THAT(run.out, HasSubstr("127.0.0.1"));
  EXPECT_THAT(run.out, ::testing::Not(HasSubstr("hunter2")));
  const RunResult check =
      RunFleetnavd({"--check-db", "--db", "postgresql://fleetnav@127.0.0.1:1/fleet"}, "pg-check");
  EXPECT_EQ(check.exit_code, 2) << check.out;
  EXPECT_THAT(check.out, HasSubstr("pg_amcheck"));
  EXPECT_EQ(RunFleetnavd({"--db", "postgresql://x@127.0.0.1:1/f", "--db-wait-s", "-3"}, "pg-bad")
                .exit_code,
            1);
}

}  // namespace
}  // namespace fleetnav
