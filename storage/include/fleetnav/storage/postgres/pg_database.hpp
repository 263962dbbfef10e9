#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"
#include "fleetnav/storage/sql/sql_database.hpp"

struct pg_conn;

namespace fleetnav::storage {

/// How PgDatabase connects and what it takes as its own.
struct PgOpenOptions {
  /// How long Open keeps trying to reach the server (back-off 0.1 s doubling to 2 s) before it
  /// gives up with UNAVAILABLE; a transaction that finds the connection lost reconnects the
  /// same way for at most `reconnect_wait_s`.
  double connect_wait_s = 10.0;
  double reconnect_wait_s = 2.0;
  /// Written into the schema table; a database whose table names another application, or that
  /// holds tables but no schema table, is refused before anything is written.
  std::string application = "fleetnav";
};

/// A PostgreSQL database through libpq, as an SqlDatabase: `?` parameters become `$1, $2, …`
/// (values sent as text, BLOBs as binary bytea), each Transaction() is BEGIN … COMMIT on one
/// connection held under a mutex, and the schema's version lives in the table
/// `fleetnav_schema`, migrated in one transaction under an advisory lock so that replicas
/// starting together migrate once. Errors keep SQLite's codes: constraint → FAILED_PRECONDITION,
/// a lost connection or server → UNAVAILABLE (the server rolls the open transaction back, so
/// nothing is half-written), bad data → INVALID_ARGUMENT. Thread-safe.
class PgDatabase final : public SqlDatabase {
 public:
  /// Connects to `conninfo` (a libpq URI, postgresql://user@host:port/db, or key=value
  /// string), checks that the database is empty or this application's, and migrates it:
  /// `migrations[i]` takes the schema from version i to i + 1. Refused, naming the database
  /// (never the password): unreachable within connect_wait_s (UNAVAILABLE), a foreign
  /// database or a schema newer than `migrations` (FAILED_PRECONDITION, naming both versions).
  static absl::StatusOr<std::unique_ptr<PgDatabase>> Open(
      const std::string& conninfo, const std::vector<std::string>& migrations,
      const PgOpenOptions& options = {});
  ~PgDatabase() override;
  PgDatabase(const PgDatabase&) = delete;
  PgDatabase& operator=(const PgDatabase&) = delete;

  absl::StatusOr<SqlStatement> Prepare(std::string_view sql) override;
  absl::Status Transaction(const std::function<absl::Status()>& body) override;
  int64_t ChangedRows() override { return changed_rows_; }
  void SetTransactionObserver(std::function<void(double seconds)> observer) override {
    transaction_observer_ = std::move(observer);
  }
  std::string Describe() const override;
  /// The schema version the database is at.
  int schema_version() const { return schema_version_; }

  // For PgStatement: the connection and the rows its last command changed (used under the
  // transaction's lock).
  pg_conn* connection() { return conn_; }
  void set_changed_rows(int64_t rows) { changed_rows_ = rows; }

 private:
  PgDatabase(std::string conninfo, PgOpenOptions options)
      : conninfo_(std::move(conninfo)), options_(std::move(options)) {}
  /// (Re)connects, trying for `wait_s` with back-off.
  absl::Status Connect(double wait_s);
  /// Runs SQL without parameters (several statements allowed).
  absl::Status Execute(std::string_view sql);
  absl::Status Migrate(const std::vector<std::string>& migrations);

  const std::string conninfo_;
  const PgOpenOptions options_;
  pg_conn* conn_ = nullptr;
  std::string target_;  ///< "database D at H:P", for messages
  int schema_version_ = 0;
  int64_t changed_rows_ = 0;
  absl::Mutex mutex_;  ///< held for a whole transaction
  std::function<void(double seconds)> transaction_observer_;
};

/// True for the `--db` values PgDatabase takes (postgresql:// and postgres:// URIs).
bool IsPostgresUri(std::string_view db);

}  // namespace fleetnav::storage
