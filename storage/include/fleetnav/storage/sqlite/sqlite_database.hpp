#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/storage/sql/sql_database.hpp"

struct sqlite3;
struct sqlite3_stmt;

namespace fleetnav::storage {

/// SQLite's side of a prepared statement (see SqlStatement). Not thread-safe; used under the
/// database's lock.
class SqliteStatement final : public SqlStatementBackend {
 public:
  SqliteStatement(sqlite3* db, sqlite3_stmt* stmt) : db_(db), stmt_(stmt) {}
  SqliteStatement(const SqliteStatement&) = delete;
  SqliteStatement& operator=(const SqliteStatement&) = delete;
  ~SqliteStatement() override;

  void Bind(int index, int64_t value) override;
  void Bind(int index, double value) override;
  void Bind(int index, std::string_view text) override;
  void BindBlob(int index, const void* data, size_t size) override;
  void BindNull(int index) override;
  absl::StatusOr<bool> Step() override;
  void Reset() override;
  int64_t ColumnInt(int column) const override;
  double ColumnDouble(int column) const override;
  std::string ColumnText(int column) const override;
  std::vector<uint8_t> ColumnBlob(int column) const override;
  bool ColumnIsNull(int column) const override;

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

/// An open SQLite database file owned by RAII (fleetnavd's embedded store): WAL journal, foreign
/// keys on, a busy timeout, and schema migrations applied in order by `PRAGMA user_version`.
/// Thread-safe: one connection serialised by an internal mutex (SQLite's serialized mode), so each
/// use case runs as one transaction through Transaction().
class SqliteDatabase final : public SqlDatabase {
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
  ~SqliteDatabase() override;
  SqliteDatabase(const SqliteDatabase&) = delete;
  SqliteDatabase& operator=(const SqliteDatabase&) = delete;

  absl::StatusOr<SqlStatement> Prepare(std::string_view sql) override;
  absl::Status Execute(std::string_view sql);
  /// Runs `body` inside BEGIN IMMEDIATE … COMMIT; rolls back when it returns an error.
  absl::Status Transaction(const std::function<absl::Status()>& body) override;
  int64_t ChangedRows() override;
  /// Nothing to do: BEGIN IMMEDIATE already runs one transaction at a time.
  absl::Status LockKey(std::string_view /*key*/) override { return absl::OkStatus(); }
  absl::StatusOr<int64_t> NextNumber(std::string_view sequence, std::string_view table,
                                     std::string_view column) override;
  void SetTransactionObserver(std::function<void(double seconds)> observer) override {
    transaction_observer_ = std::move(observer);
  }
  std::string Describe() const override { return "SQLite file " + path_; }
  int user_version();

 private:
  SqliteDatabase(sqlite3* db, std::string path) : db_(db), path_(std::move(path)) {}
  /// Empty when `options` take this file as their own, else why not. Reads only.
  absl::StatusOr<std::string> OwnershipProblem(const SqliteOpenOptions& options);
  absl::StatusOr<int64_t> QueryInt(std::string_view sql);
  absl::Status Migrate(const std::vector<std::string>& migrations);

  sqlite3* db_;
  const std::string path_;
  std::function<void(double seconds)> transaction_observer_;
};

/// Converts an SQLite result code and the connection's message into a Status.
absl::Status SqliteError(sqlite3* db, int code, const std::string& what);

}  // namespace fleetnav::storage
