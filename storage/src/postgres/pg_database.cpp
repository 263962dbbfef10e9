#include "fleetnav/storage/postgres/pg_database.hpp"

#include <libpq-fe.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <optional>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/time/clock.h"
#include "absl/time/time.h"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/storage/postgres/pg_site_leases.hpp"

namespace fleetnav::storage {

/// A pooled connection: the libpq connection, the rows its last command changed, and the
/// SQLSTATE of its transaction's last error (what decides a retry).
struct PgConnection {
  PGconn* conn = nullptr;
  int64_t changed_rows = 0;
  std::string failed_state;
  bool body_started = false;  ///< the current attempt got past BEGIN
};

namespace {

/// Advisory-lock key of schema migrations: "FNAV", as SQLite's application_id.
constexpr int64_t kMigrationLockKey = 0x464E4156;
/// Tries of a transaction that raced another one for a key or was aborted by the server.
constexpr int kMaxAttempts = 20;

/// An SQLSTATE and message as a Status with the codes SqliteError gives.
absl::Status PgError(const PGresult* result, PGconn* conn, const std::string& what) {
  const char* state = result != nullptr ? PQresultErrorField(result, PG_DIAG_SQLSTATE) : nullptr;
  const char* primary =
      result != nullptr ? PQresultErrorField(result, PG_DIAG_MESSAGE_PRIMARY) : nullptr;
  std::string message =
      absl::StrCat(what, ": ", primary != nullptr ? primary : PQerrorMessage(conn));
  while (!message.empty() && message.back() == '\n') message.pop_back();
  if (PQstatus(conn) != CONNECTION_OK) return absl::UnavailableError(message);
  const std::string code = state != nullptr ? state : "";
  const std::string category = code.substr(0, 2);
  if (category == "23") return absl::FailedPreconditionError(message);
  if (category == "22") return absl::InvalidArgumentError(message);
  if (category == "08" || category == "40" || category == "53" || category == "57") {
    return absl::UnavailableError(message);
  }
  if (code == "XX001" || code == "XX002") return absl::DataLossError(message);
  return absl::InternalError(message);
}

/// Owns a PGresult.
struct ResultDeleter {
  void operator()(PGresult* result) const { PQclear(result); }
};
using PgResult = std::unique_ptr<PGresult, ResultDeleter>;

bool Succeeded(const PGresult* result) {
  const ExecStatusType status = PQresultStatus(result);
  return status == PGRES_COMMAND_OK || status == PGRES_TUPLES_OK;
}

/// `?` parameters (outside quotes) as `$1, $2, …`.
std::string NumberParameters(std::string_view sql) {
  std::string out;
  out.reserve(sql.size() + 16);
  bool quoted = false;
  int next = 1;
  for (char c : sql) {
    if (c == '\'') quoted = !quoted;
    if (c == '?' && !quoted) {
      absl::StrAppend(&out, "$", next++);
    } else {
      out.push_back(c);
    }
  }
  return out;
}

/// The SQLSTATE of a failed result ("" when unknown).
std::string SqlState(const PGresult* result) {
  const char* state = result != nullptr ? PQresultErrorField(result, PG_DIAG_SQLSTATE) : nullptr;
  return state != nullptr ? state : "";
}

/// Runs SQL without parameters on `connection`.
absl::Status ExecuteOn(PgConnection* connection, std::string_view sql) {
  PgResult result(PQexec(connection->conn, std::string(sql).c_str()));
  if (result == nullptr || !Succeeded(result.get())) {
    connection->failed_state = SqlState(result.get());
    return PgError(result.get(), connection->conn, "postgresql");
  }
  return absl::OkStatus();
}

/// One statement on a transaction's connection: parameters kept as text (or binary for
/// BLOBs) until the first Step() sends them; rows are read from the whole result.
class PgStatement final : public SqlStatementBackend {
 public:
  PgStatement(PgConnection* connection, std::string sql)
      : connection_(connection), sql_(std::move(sql)) {}

  void Bind(int index, int64_t value) override { Set(index, absl::StrCat(value), false); }
  void Bind(int index, double value) override {
    Set(index, absl::StrFormat("%.17g", value), false);
  }
  void Bind(int index, std::string_view text) override { Set(index, std::string(text), false); }
  void BindBlob(int index, const void* data, size_t size) override {
    Set(index, std::string(static_cast<const char*>(data), size), true);
  }
  void BindNull(int index) override {
    Grow(index);
    values_[index - 1].reset();
  }

  absl::StatusOr<bool> Step() override {
    if (result_ == nullptr) {
      std::vector<const char*> values(values_.size());
      std::vector<int> lengths(values_.size()), formats(values_.size());
      for (size_t i = 0; i < values_.size(); ++i) {
        values[i] = values_[i].has_value() ? values_[i]->data() : nullptr;
        lengths[i] = values_[i].has_value() ? static_cast<int>(values_[i]->size()) : 0;
        formats[i] = binary_[i] ? 1 : 0;
      }
      result_.reset(PQexecParams(connection_->conn, sql_.c_str(), static_cast<int>(values.size()),
                                 nullptr, values.data(), lengths.data(), formats.data(), 0));
      if (result_ == nullptr || !Succeeded(result_.get())) {
        connection_->failed_state = SqlState(result_.get());
        absl::Status error = PgError(result_.get(), connection_->conn, "postgresql");
        result_.reset();
        return error;
      }
      const char* changed = PQcmdTuples(result_.get());
      connection_->changed_rows = changed[0] != '\0' ? std::strtoll(changed, nullptr, 10) : 0;
      row_ = -1;
    }
    return ++row_ < PQntuples(result_.get());
  }

  void Reset() override {
    result_.reset();
    values_.clear();
    binary_.clear();
  }

  int64_t ColumnInt(int column) const override { return std::strtoll(Value(column), nullptr, 10); }
  double ColumnDouble(int column) const override { return std::strtod(Value(column), nullptr); }
  std::string ColumnText(int column) const override {
    return std::string(Value(column),
                       static_cast<size_t>(PQgetlength(result_.get(), row_, column)));
  }
  std::vector<uint8_t> ColumnBlob(int column) const override {
    size_t length = 0;
    unsigned char* bytes =
        PQunescapeBytea(reinterpret_cast<const unsigned char*>(Value(column)), &length);
    if (bytes == nullptr) return {};
    std::vector<uint8_t> out(bytes, bytes + length);
    PQfreemem(bytes);
    return out;
  }
  bool ColumnIsNull(int column) const override {
    return PQgetisnull(result_.get(), row_, column) == 1;
  }

 private:
  void Grow(int index) {
    if (static_cast<int>(values_.size()) < index) {
      values_.resize(index);
      binary_.resize(index, false);
    }
  }
  void Set(int index, std::string value, bool binary) {
    Grow(index);
    values_[index - 1] = std::move(value);
    binary_[index - 1] = binary;
  }
  const char* Value(int column) const { return PQgetvalue(result_.get(), row_, column); }

  PgConnection* connection_;
  const std::string sql_;
  std::vector<std::optional<std::string>> values_;
  std::vector<bool> binary_;
  PgResult result_;
  int row_ = -1;
};

void IgnoreNotice(void* /*arg*/, const char* /*message*/) {}

}  // namespace

bool IsPostgresUri(std::string_view db) {
  return db.rfind("postgresql://", 0) == 0 || db.rfind("postgres://", 0) == 0;
}

absl::StatusOr<std::unique_ptr<PgDatabase>> PgDatabase::Open(
    const std::string& conninfo, const std::vector<std::string>& migrations,
    const PgOpenOptions& options) {
  if (options.connections < 1 || options.connections > 256) {
    return absl::InvalidArgumentError(
        absl::StrCat("connections: must be in [1, 256], got ", options.connections));
  }
  if (options.fence.has_value()) RETURN_IF_ERROR(ValidateSiteName(options.fence->site));
  std::unique_ptr<PgDatabase> db(new PgDatabase(conninfo, options));
  RETURN_IF_ERROR(db->Connect(db->pool_.front().get(), options.connect_wait_s));
  absl::Status migrated = db->Migrate(migrations);
  if (!migrated.ok()) {
    return absl::Status(migrated.code(), absl::StrCat(db->Describe(), ": ", migrated.message()));
  }
  return db;
}

PgDatabase::PgDatabase(std::string conninfo, PgOpenOptions options)
    : conninfo_(std::move(conninfo)), options_(std::move(options)) {
  for (int i = 0; i < options_.connections; ++i) {
    pool_.push_back(std::make_unique<PgConnection>());
    free_.push_back(pool_.back().get());
  }
  if (options_.fence.has_value()) {
    // The site name is checked (letters, digits, '_', '-', '.'), so it is safe as a literal;
    // the lock and the read go in one round trip, each statement with its own snapshot, so
    // the read sees any takeover that committed before the lock was granted.
    fence_sql_ =
        absl::StrCat("SELECT pg_advisory_xact_lock_shared(", kSiteLeaseLockClass, ", hashtext('",
                     options_.fence->site, "')); SELECT epoch FROM site_leases WHERE site = '",
                     options_.fence->site, "'");
  }
}

PgDatabase::~PgDatabase() {
  for (const std::unique_ptr<PgConnection>& connection : pool_) {
    if (connection->conn != nullptr) PQfinish(connection->conn);
  }
}

std::string PgDatabase::Describe() const { return absl::StrCat("PostgreSQL ", target_); }

absl::Status PgDatabase::Connect(PgConnection* connection, double wait_s) {
  const absl::Time deadline = absl::Now() + absl::Seconds(wait_s);
  absl::Duration backoff = absl::Milliseconds(100);
  while (true) {
    if (connection->conn != nullptr) PQfinish(connection->conn);
    connection->conn = PQconnectdb(conninfo_.c_str());
    PGconn* conn = connection->conn;
    if (conn != nullptr && PQstatus(conn) == CONNECTION_OK) {
      PQsetNoticeProcessor(conn, IgnoreNotice, nullptr);
      if (options_.fence.has_value()) {
        const std::string timeout_sql =
            absl::StrCat("SET idle_in_transaction_session_timeout = ",
                         static_cast<int64_t>(options_.idle_in_transaction_timeout_s * 1000));
        PgResult set(PQexec(conn, timeout_sql.c_str()));
        if (set == nullptr || !Succeeded(set.get())) {
          return PgError(set.get(), conn, "setting idle_in_transaction_session_timeout");
        }
      }
      absl::MutexLock lock(&pool_mutex_);
      if (target_.empty()) {
        target_ = absl::StrCat("database ", PQdb(conn), " at ", PQhost(conn), ":", PQport(conn));
      }
      return absl::OkStatus();
    }
    std::string why = conn != nullptr ? PQerrorMessage(conn) : "out of memory";
    while (!why.empty() && (why.back() == '\n' || why.back() == ' ')) why.pop_back();
    if (absl::Now() + backoff > deadline) {
      // libpq's messages name host and port but never the password.
      return absl::UnavailableError(
          absl::StrCat("cannot reach PostgreSQL within ", wait_s, " s: ", why));
    }
    absl::SleepFor(backoff);
    backoff = std::min(backoff * 2, absl::Seconds(2));
  }
}

PgConnection* PgDatabase::Current() {
  absl::MutexLock lock(&pool_mutex_);
  const auto held = held_.find(std::this_thread::get_id());
  return held != held_.end() ? held->second : nullptr;
}

PgConnection* PgDatabase::Acquire() {
  absl::MutexLock lock(&pool_mutex_);
  pool_mutex_.Await(absl::Condition(
      +[](std::vector<PgConnection*>* free) { return !free->empty(); }, &free_));
  PgConnection* connection = free_.back();
  free_.pop_back();
  held_[std::this_thread::get_id()] = connection;
  return connection;
}

void PgDatabase::Release(PgConnection* connection) {
  absl::MutexLock lock(&pool_mutex_);
  held_.erase(std::this_thread::get_id());
  free_.push_back(connection);
}

int64_t PgDatabase::ChangedRows() {
  PgConnection* connection = Current();
  return connection != nullptr ? connection->changed_rows : 0;
}

absl::Status PgDatabase::Execute(std::string_view sql) {
  PgConnection* connection = Current();
  if (connection == nullptr) return absl::InternalError("SQL outside a transaction");
  return ExecuteOn(connection, sql);
}

absl::Status PgDatabase::LockKey(std::string_view key) {
  // hashtext() maps the key to the advisory lock's 32-bit key space (collisions only serialize).
  ASSIGN_OR_RETURN(SqlStatement lock, Prepare("SELECT pg_advisory_xact_lock(hashtext(?))"));
  lock.Bind(1, key);
  return lock.Run();
}

absl::StatusOr<int64_t> PgDatabase::NextNumber(std::string_view sequence,
                                               std::string_view /*table*/,
                                               std::string_view /*column*/) {
  ASSIGN_OR_RETURN(SqlStatement next, Prepare("SELECT nextval(CAST(? AS regclass))"));
  next.Bind(1, sequence);
  ASSIGN_OR_RETURN(const bool row, next.Step());
  if (!row)
    return absl::InternalError(absl::StrCat("nextval('", std::string(sequence), "') gave no row"));
  return next.ColumnInt(0);
}

absl::StatusOr<SqlStatement> PgDatabase::Prepare(std::string_view sql) {
  PgConnection* connection = Current();
  if (connection == nullptr) return absl::InternalError("SQL outside a transaction");
  return SqlStatement(std::make_unique<PgStatement>(connection, NumberParameters(sql)));
}

absl::Status PgDatabase::Attempt(PgConnection* connection,
                                 const std::function<absl::Status()>& body) {
  connection->failed_state.clear();
  connection->body_started = false;
  if (PQstatus(connection->conn) != CONNECTION_OK) {
    // Not opened yet, or the server restarted or the network broke since its last use.
    RETURN_IF_ERROR(Connect(connection, options_.reconnect_wait_s));
  }
  RETURN_IF_ERROR(ExecuteOn(connection, "BEGIN"));
  connection->changed_rows = 0;
  connection->body_started = true;
  absl::Status status = fence_sql_.empty() ? absl::OkStatus() : CheckFence(connection);
  if (status.ok()) status = body();
  if (status.ok()) return ExecuteOn(connection, "COMMIT");
  if (PQstatus(connection->conn) == CONNECTION_OK) (void)ExecuteOn(connection, "ROLLBACK");
  return status;
}

absl::Status PgDatabase::CheckFence(PgConnection* connection) {
  PgResult result(PQexec(connection->conn, fence_sql_.c_str()));
  if (result == nullptr || !Succeeded(result.get())) {
    connection->failed_state = SqlState(result.get());
    return PgError(result.get(), connection->conn, "checking the site lease");
  }
  const int64_t epoch =
      PQntuples(result.get()) == 1 ? std::strtoll(PQgetvalue(result.get(), 0, 0), nullptr, 10) : 0;
  if (epoch != options_.fence->epoch) {
    return absl::FailedPreconditionError(absl::StrCat(
        "leadership of site '", options_.fence->site, "' lost: its lease is at epoch ", epoch,
        ", this replica led at epoch ", options_.fence->epoch, "; nothing written"));
  }
  return absl::OkStatus();
}

absl::Status PgDatabase::Transaction(const std::function<absl::Status()>& body) {
  const auto started = std::chrono::steady_clock::now();
  PgConnection* connection = Acquire();
  absl::Status status;
  bool reconnected = false;
  for (int attempt = 1; attempt <= kMaxAttempts; ++attempt) {
    const bool looked_open = PQstatus(connection->conn) == CONNECTION_OK;
    status = Attempt(connection, body);
    if (status.ok()) break;
    // A race for a new key (unique_violation), a serialization failure or a deadlock: the
    // transaction was rolled back as a whole; run it again.
    const std::string& state = connection->failed_state;
    if (state == "23505" || state == "40001" || state == "40P01") continue;
    // A pooled connection that died while idle (the server restarted since its last use) fails
    // at BEGIN, before anything ran: once, reconnect and run it again.
    if (looked_open && !connection->body_started && !reconnected &&
        PQstatus(connection->conn) != CONNECTION_OK) {
      reconnected = true;
      continue;
    }
    break;
  }
  Release(connection);
  if (status.ok() && transaction_observer_) {
    transaction_observer_(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
  }
  return status;
}

absl::Status PgDatabase::Migrate(const std::vector<std::string>& migrations) {
  return Transaction([&]() -> absl::Status {
    // Replicas starting together: the first migrates, the others wait here and find it done.
    RETURN_IF_ERROR(Execute(absl::StrCat("SELECT pg_advisory_xact_lock(", kMigrationLockKey, ")")));
    ASSIGN_OR_RETURN(SqlStatement has_table,
                     Prepare("SELECT COUNT(*) FROM information_schema.tables WHERE "
                             "table_schema = current_schema() AND table_name = 'fleetnav_schema'"));
    ASSIGN_OR_RETURN(bool row, has_table.Step());
    if (!row) return absl::InternalError("cannot read information_schema");
    if (has_table.ColumnInt(0) == 0) {
      ASSIGN_OR_RETURN(SqlStatement tables,
                       Prepare("SELECT COUNT(*) FROM information_schema.tables WHERE "
                               "table_schema = current_schema()"));
      ASSIGN_OR_RETURN(row, tables.Step());
      if (row && tables.ColumnInt(0) > 0) {
        return absl::FailedPreconditionError(
            absl::StrCat("not a fleetnav database (", tables.ColumnInt(0),
                         " tables and no fleetnav_schema table); refusing to write to it"));
      }
      RETURN_IF_ERROR(Execute(
          "CREATE TABLE fleetnav_schema (application TEXT NOT NULL, version INTEGER NOT NULL)"));
      ASSIGN_OR_RETURN(SqlStatement stamp,
                       Prepare("INSERT INTO fleetnav_schema (application, version) VALUES (?, 0)"));
      stamp.Bind(1, options_.application);
      RETURN_IF_ERROR(stamp.Run());
    }
    ASSIGN_OR_RETURN(SqlStatement current,
                     Prepare("SELECT application, version FROM fleetnav_schema"));
    ASSIGN_OR_RETURN(row, current.Step());
    if (!row) return absl::FailedPreconditionError("fleetnav_schema holds no row");
    if (current.ColumnText(0) != options_.application) {
      return absl::FailedPreconditionError(absl::StrCat("the database belongs to '",
                                                        current.ColumnText(0), "', not '",
                                                        options_.application, "'"));
    }
    const int version = static_cast<int>(current.ColumnInt(1));
    if (version > static_cast<int>(migrations.size())) {
      return absl::FailedPreconditionError(
          absl::StrCat("database schema version ", version, " is newer than this binary's ",
                       migrations.size(), "; run a fleetnavd as new as the database"));
    }
    for (int next = version; next < static_cast<int>(migrations.size()); ++next) {
      RETURN_IF_ERROR(Execute(migrations[next]));
    }
    ASSIGN_OR_RETURN(SqlStatement stamp, Prepare("UPDATE fleetnav_schema SET version = ?"));
    stamp.Bind(1, static_cast<int64_t>(migrations.size()));
    RETURN_IF_ERROR(stamp.Run());
    schema_version_ = static_cast<int>(migrations.size());
    return absl::OkStatus();
  });
}

}  // namespace fleetnav::storage
