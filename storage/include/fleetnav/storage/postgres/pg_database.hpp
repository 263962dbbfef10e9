#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/container/flat_hash_map.h"
#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"
#include "fleetnav/storage/sql/sql_database.hpp"

namespace fleetnav::storage {

/// One pooled connection of a PgDatabase (defined in pg_database.cpp).
struct PgConnection;

/// The fencing token of a site leader's writes: the lease epoch its replica won (PgSiteLeases).
struct PgFence {
  std::string site;
  int64_t epoch = 0;
};

/// How PgDatabase connects and what it takes as its own.
struct PgOpenOptions {
  /// How long Open keeps trying to reach the server (back-off 0.1 s doubling to 2 s) before it
  /// gives up with UNAVAILABLE; a transaction that finds the connection lost reconnects the
  /// same way for at most `reconnect_wait_s`.
  double connect_wait_s = 10.0;
  double reconnect_wait_s = 2.0;
  /// Connections, so that this many transactions run at once (each on its own); opened as
  /// they are first needed.
  int connections = 4;
  /// Written into the schema table; a database whose table names another application, or that
  /// holds tables but no schema table, is refused before anything is written.
  std::string application = "fleetnav";
  /// Set on the store of a site's leader replica: every transaction first takes the site's
  /// lease lock shared and checks that the lease is still at this epoch, or fails
  /// FAILED_PRECONDITION having written nothing. A replica taking the lease over takes that
  /// lock exclusively, so no write of the old leader can land after the takeover; and a leader
  /// paused inside a transaction is rolled back by the server after
  /// `idle_in_transaction_timeout_s`, so it cannot hold a takeover up for longer.
  std::optional<PgFence> fence;
  double idle_in_transaction_timeout_s = 3.0;
};

/// A PostgreSQL database through libpq, as an SqlDatabase: `?` parameters become `$1, $2, …`
/// (values sent as text, BLOBs as binary bytea), and each Transaction() is BEGIN … COMMIT on a
/// connection of a pool that the calling thread holds until COMMIT, so several transactions run
/// at once. Two that raced for the same new key (the next version of a map, the next job
/// number; unique_violation) or that the server aborted (serialization failure, deadlock) are
/// run again, up to 20 times, so a Transaction() body may run more than once and must assign
/// its results rather than append to them. The schema's version lives in the table
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
  int64_t ChangedRows() override;
  /// pg_advisory_xact_lock of the key's hash, released at COMMIT or ROLLBACK.
  absl::Status LockKey(std::string_view key) override;
  /// nextval of the sequence.
  absl::StatusOr<int64_t> NextNumber(std::string_view sequence, std::string_view table,
                                     std::string_view column) override;
  void SetTransactionObserver(std::function<void(double seconds)> observer) override {
    transaction_observer_ = std::move(observer);
  }
  std::string Describe() const override;
  /// The schema version the database is at.
  int schema_version() const { return schema_version_; }

 private:
  PgDatabase(std::string conninfo, PgOpenOptions options);
  /// (Re)connects `connection`, trying for `wait_s` with back-off.
  absl::Status Connect(PgConnection* connection, double wait_s);
  /// The connection the calling thread holds in its transaction (null outside one).
  PgConnection* Current();
  PgConnection* Acquire();
  void Release(PgConnection* connection);
  /// One attempt of a transaction on `connection`.
  absl::Status Attempt(PgConnection* connection, const std::function<absl::Status()>& body);
  /// Runs SQL without parameters (several statements allowed) in the current transaction.
  absl::Status Execute(std::string_view sql);
  absl::Status Migrate(const std::vector<std::string>& migrations);
  /// With a fence: the lease lock (shared) and the epoch check, first in each transaction.
  absl::Status CheckFence(PgConnection* connection);

  const std::string conninfo_;
  const PgOpenOptions options_;
  std::vector<std::unique_ptr<PgConnection>> pool_;
  absl::Mutex pool_mutex_;
  std::vector<PgConnection*> free_ ABSL_GUARDED_BY(pool_mutex_);
  absl::flat_hash_map<std::thread::id, PgConnection*> held_ ABSL_GUARDED_BY(pool_mutex_);
  std::string fence_sql_;  ///< the fence's lock and epoch query; empty without a fence
  std::string target_;     ///< "database D at H:P", for messages; set by the first connection
  int schema_version_ = 0;
  std::function<void(double seconds)> transaction_observer_;
};

/// True for the `--db` values PgDatabase takes (postgresql:// and postgres:// URIs).
bool IsPostgresUri(std::string_view db);

}  // namespace fleetnav::storage
