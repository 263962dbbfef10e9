#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <memory>
#include <ostream>
#include <string>

#include "absl/strings/str_cat.h"
#include "fleetnav/storage/fleet_database.hpp"
#include "postgres_server.hpp"
#include "temp_db_path.hpp"

namespace fleetnav::storage::testing {

/// Which implementation a conformance suite runs over: the in-memory fake, SQLite on a real
/// temporary file, or PostgreSQL on a real server (fleetnav::testing::SharedPostgres).
enum class Backend { kMemory, kSqlite, kPostgres };

inline std::string BackendName(Backend backend) {
  switch (backend) {
    case Backend::kMemory:
      return "Memory";
    case Backend::kSqlite:
      return "Sqlite";
    case Backend::kPostgres:
      return "Postgres";
  }
  return "Unknown";
}

inline void PrintTo(Backend backend, std::ostream* os) { *os << BackendName(backend); }

inline std::string BackendTestName(const ::testing::TestParamInfo<Backend>& info) {
  return BackendName(info.param);
}

/// A new, empty fleet database of an SQL backend, opened through OpenFleetDatabase as fleetnavd
/// opens it (null for kMemory); closed and removed at the end.
class TestDatabase {
 public:
  explicit TestDatabase(Backend backend) { Open(backend); }
  ~TestDatabase() {
    db_.reset();  // closes the file before TempDbPath removes it
  }
  SqlDatabase* get() const { return db_.get(); }

 private:
  void Open(Backend backend) {
    std::string where;
    if (backend == Backend::kSqlite) {
      path_ = std::make_unique<TempDbPath>();
      where = path_->path();
    } else if (backend == Backend::kPostgres) {
      absl::StatusOr<std::string> uri = fleetnav::testing::NewSharedDatabase("test");
      ASSERT_TRUE(uri.ok()) << uri.status();
      where = *uri;
    } else {
      return;
    }
    absl::StatusOr<std::unique_ptr<SqlDatabase>> db = OpenFleetDatabase(where);
    ASSERT_TRUE(db.ok()) << db.status();
    db_ = *std::move(db);
  }

  std::unique_ptr<TempDbPath> path_;
  std::unique_ptr<SqlDatabase> db_;
};

}  // namespace fleetnav::storage::testing
