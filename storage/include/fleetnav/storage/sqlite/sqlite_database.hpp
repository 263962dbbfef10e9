#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"

struct sqlite3;
struct sqlite3_stmt;

namespace fleetnav::storage {

/// A prepared statement owned by RAII. Bind parameters are 1-based as in SQLite. Step()
/// returns true while a row is available. Not thread-safe; used under the database's lock.
class SqliteStatement {
 public:
  SqliteStatement(sqlite3* db, sqlite3_stmt* stmt) : db_(db), stmt_(stmt) {}
  SqliteStatement(SqliteStatement&& other) noexcept;
  SqliteStatement& operator=(SqliteStatement&&) = delete;
  SqliteStatement(const SqliteStatement&) = delete;
  ~SqliteStatement();

  SqliteStatement& Bind(int index, int64_t value);
  SqliteStatement& Bind(int index, double value);
  SqliteStatement& Bind(int index, std::string_view text);
  SqliteStatement& BindBlob(int index, const void* data, size_t size);
  SqliteStatement& BindNull(int index);

  /// True when a row is ready, false when done; errors as Internal/Unavailable.
  absl::StatusOr<bool> Step();
  /// Steps to completion, expecting no rows.
  absl::Status Run();
  void Reset();

  int64_t ColumnInt(int column) const;
  double ColumnDouble(int column) const;
  std::string ColumnText(int column) const;
  std::vector<uint8_t> ColumnBlob(int column) const;
  bool ColumnIsNull(int column) const;

 private:
  sqlite3* db_;
  sqlite3_stmt* stmt_;
};

/// Durability of committed transactions. kFull (the default) makes every acknowledged commit
/// survive `kill -9` and power loss: WAL journal with synchronous=FULL, so a commit returns
/// only after the WAL is fsynced.
enum class Durability { kFull, kNormal };

/// How a database file is opened: its durability, and which files the schema may take as its
/// own. With a non-zero `application_id`, a file is taken only when it carries that
/// `PRAGMA application_id`, is empty (it is then stamped with it), or carries no id but holds
/// `legacy_table` (a file of this schema written before ids were stamped). Any other file is
/// refused before anything is written to it.
struct SqliteOpenOptions {
  Durability durability = Durability::kFull;
  uint32_t application_id = 0;
  std::string legacy_table;
};

/// What `SqliteDatabase::Check` found in a file, read without writing to it.
struct SqliteCheckReport {
  int schema_version = 0;
  /// `PRAGMA integrity_check` lines other than "ok" (at most 20), and ownership problems.
  std::vector<std::string> problems;
  bool ok() const { return problems.empty(); }
};

/// An open SQLite database file owned by RAII: WAL journal, foreign keys on, a busy timeout,
/// and schema migrations applied in order by `PRAGMA user_version`. Thread-safe: one
/// connection serialised by an internal mutex (SQLite's serialized mode), so each use case
/// runs as one transaction through Transaction().
class SqliteDatabase {
 public:
  /// Opens (creating if needed), checks and migrates. `migrations[i]` takes user_version i to
  /// i+1. Refused, naming the file, before anything is written: a file the options do not
  /// take as their own (FailedPrecondition), a read-only file (FailedPrecondition), a file that
  /// fails `PRAGMA quick_check` or is no SQLite database (DataLoss), a schema newer than
  /// `migrations` (FailedPrecondition).
  static absl::StatusOr<std::unique_ptr<SqliteDatabase>> Open(
      const std::string& path, const std::vector<std::string>& migrations,
      const SqliteOpenOptions& options = {});
  /// Reads an existing file without writing to it: its ownership as Open judges it and
  /// `PRAGMA integrity_check`. An error only when the file cannot be read at all.
  static absl::StatusOr<SqliteCheckReport> Check(const std::string& path,
                                                 const SqliteOpenOptions& options);
  ~SqliteDatabase();
  SqliteDatabase(const SqliteDatabase&) = delete;
  SqliteDatabase& operator=(const SqliteDatabase&) = delete;

  absl::StatusOr<SqliteStatement> Prepare(std::string_view sql);
  absl::Status Execute(std::string_view sql);
  /// Runs `body` inside BEGIN IMMEDIATE … COMMIT; rolls back when it returns an error.
  absl::Status Transaction(const std::function<absl::Status()>& body);
  /// Told how long each committed transaction took, lock wait included (fleetnavd's store write
  /// latency metric). Set once, before the database is shared between threads.
  void SetTransactionObserver(std::function<void(double seconds)> observer) {
    transaction_observer_ = std::move(observer);
  }
  int user_version();

 private:
  explicit SqliteDatabase(sqlite3* db) : db_(db) {}
  /// Empty when `options` take this file as their own, else why not. Reads only.
  absl::StatusOr<std::string> OwnershipProblem(const SqliteOpenOptions& options);
  absl::StatusOr<int64_t> QueryInt(std::string_view sql);
  absl::Status Migrate(const std::vector<std::string>& migrations);

  sqlite3* db_;
  std::function<void(double seconds)> transaction_observer_;
};

/// Converts an SQLite result code and the connection's message into a Status.
absl::Status SqliteError(sqlite3* db, int code, const std::string& what);

}  // namespace fleetnav::storage
