#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"

namespace fleetnav::storage {

/// What a database engine does for one statement; SqlStatement is the handle the
/// repositories hold. Parameters are 1-based and written `?` in the SQL.
class SqlStatementBackend {
 public:
  virtual ~SqlStatementBackend() = default;
  virtual void Bind(int index, int64_t value) = 0;
  virtual void Bind(int index, double value) = 0;
  virtual void Bind(int index, std::string_view text) = 0;
  virtual void BindBlob(int index, const void* data, size_t size) = 0;
  virtual void BindNull(int index) = 0;
  virtual absl::StatusOr<bool> Step() = 0;
  virtual void Reset() = 0;
  virtual int64_t ColumnInt(int column) const = 0;
  virtual double ColumnDouble(int column) const = 0;
  virtual std::string ColumnText(int column) const = 0;
  virtual std::vector<uint8_t> ColumnBlob(int column) const = 0;
  virtual bool ColumnIsNull(int column) const = 0;
};

/// A prepared statement of any SqlDatabase, owned by RAII. Bind parameters are 1-based; Step()
/// returns true while a row is available; Reset() clears the bindings and lets it run again.
/// Not thread-safe: used inside one SqlDatabase::Transaction.
class SqlStatement {
 public:
  explicit SqlStatement(std::unique_ptr<SqlStatementBackend> backend)
      : backend_(std::move(backend)) {}

  SqlStatement& Bind(int index, int64_t value) {
    backend_->Bind(index, value);
    return *this;
  }
  SqlStatement& Bind(int index, double value) {
    backend_->Bind(index, value);
    return *this;
  }
  SqlStatement& Bind(int index, std::string_view text) {
    backend_->Bind(index, text);
    return *this;
  }
  SqlStatement& BindBlob(int index, const void* data, size_t size) {
    backend_->BindBlob(index, data, size);
    return *this;
  }
  SqlStatement& BindNull(int index) {
    backend_->BindNull(index);
    return *this;
  }

  /// True when a row is ready, false when done; errors as Internal/Unavailable/...
  absl::StatusOr<bool> Step() { return backend_->Step(); }
  /// Steps to completion, ignoring rows.
  absl::Status Run();
  void Reset() { backend_->Reset(); }

  int64_t ColumnInt(int column) const { return backend_->ColumnInt(column); }
  double ColumnDouble(int column) const { return backend_->ColumnDouble(column); }
  std::string ColumnText(int column) const { return backend_->ColumnText(column); }
  std::vector<uint8_t> ColumnBlob(int column) const { return backend_->ColumnBlob(column); }
  bool ColumnIsNull(int column) const { return backend_->ColumnIsNull(column); }

 private:
  std::unique_ptr<SqlStatementBackend> backend_;
};

/// fleetnavd's store as the repositories see it: prepared statements in the SQL both engines
/// speak (`?` parameters, INSERT … ON CONFLICT, COALESCE), grouped into transactions. SQLite
/// (an embedded file) and PostgreSQL (a server shared by replicas) implement it; a schema of
/// each engine's dialect makes the tables. Thread-safe: each use case runs as one
/// Transaction(), and statements are prepared only inside one.
class SqlDatabase {
 public:
  virtual ~SqlDatabase() = default;
  virtual absl::StatusOr<SqlStatement> Prepare(std::string_view sql) = 0;
  /// Runs `body` inside BEGIN … COMMIT; rolls back when it returns an error.
  virtual absl::Status Transaction(const std::function<absl::Status()>& body) = 0;
  /// Holds `key` until the current transaction ends, so that transactions that number new rows
  /// from what they read (the next version of a map, the next job) take their turns. SQLite's
  /// transactions already run one at a time; PostgreSQL takes an advisory lock.
  virtual absl::Status LockKey(std::string_view key) = 0;
  /// The number of a new row of `table`, numbered by its integer `column`, inside the current
  /// transaction. SQLite, one writer at a time, reads the largest number + 1; PostgreSQL takes
  /// the next value of the sequence `sequence` (created by its schema), so that writers
  /// numbering rows at once do not wait for each other: numbers of transactions rolled back
  /// are then skipped.
  virtual absl::StatusOr<int64_t> NextNumber(std::string_view sequence, std::string_view table,
                                             std::string_view column) = 0;
  /// Rows the last INSERT, UPDATE or DELETE of the current transaction changed.
  virtual int64_t ChangedRows() = 0;
  /// Told how long each committed transaction took, lock wait included (fleetnavd's store write
  /// latency metric). Set once, before the database is shared between threads.
  virtual void SetTransactionObserver(std::function<void(double seconds)> observer) = 0;
  /// Which engine and where, for messages ("SQLite file fleet.db").
  virtual std::string Describe() const = 0;
};

}  // namespace fleetnav::storage
