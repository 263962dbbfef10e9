#include "fleetnav/storage/sqlite/sqlite_database.hpp"

#include <sqlite3.h>

#include <chrono>
#include <mutex>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "fleetnav/core/status_macros.hpp"

namespace fleetnav::storage {

absl::Status SqliteError(sqlite3* db, int code, const std::string& what) {
  std::string message = absl::StrCat(what, ": ", db ? sqlite3_errmsg(db) : sqlite3_errstr(code));
  switch (code & 0xff) {
    case SQLITE_BUSY:
    case SQLITE_LOCKED:
      return absl::UnavailableError(message);
    case SQLITE_CONSTRAINT:
    case SQLITE_READONLY:
      return absl::FailedPreconditionError(message);
    case SQLITE_CORRUPT:
    case SQLITE_NOTADB:
      return absl::DataLossError(message);
    case SQLITE_FULL:
    case SQLITE_IOERR:
    case SQLITE_CANTOPEN:
      return absl::UnavailableError(message);
    default:
      return absl::InternalError(message);
  }
}

SqliteStatement::~SqliteStatement() {
  if (stmt_ != nullptr) sqlite3_finalize(stmt_);
}

void SqliteStatement::Bind(int index, int64_t value) { sqlite3_bind_int64(stmt_, index, value); }

void SqliteStatement::Bind(int index, double value) { sqlite3_bind_double(stmt_, index, value); }

void SqliteStatement::Bind(int index, std::string_view text) {
  sqlite3_bind_text(stmt_, index, text.data(), static_cast<int>(text.size()), SQLITE_TRANSIENT);
}

void SqliteStatement::BindBlob(int index, const void* data, size_t size) {
  sqlite3_bind_blob64(stmt_, index, data, size, SQLITE_TRANSIENT);
}

void SqliteStatement::BindNull(int index) { sqlite3_bind_null(stmt_, index); }

absl::StatusOr<bool> SqliteStatement::Step() {
  const int code = sqlite3_step(stmt_);
  if (code == SQLITE_ROW) return true;
  if (code == SQLITE_DONE) return false;
  return SqliteError(db_, code, "sqlite step");
}

void SqliteStatement::Reset() {
  sqlite3_reset(stmt_);
  sqlite3_clear_bindings(stmt_);
}

int64_t SqliteStatement::ColumnInt(int column) const { return sqlite3_column_int64(stmt_, column); }

double SqliteStatement::ColumnDouble(int column) const {
  return sqlite3_column_double(stmt_, column);
}

std::string SqliteStatement::ColumnText(int column) const {
  const auto* text = sqlite3_column_text(stmt_, column);
  const int size = sqlite3_column_bytes(stmt_, column);
  return text ? std::string(reinterpret_cast<const char*>(text), size) : std::string();
}

std::vector<uint8_t> SqliteStatement::ColumnBlob(int column) const {
  const auto* data = static_cast<const uint8_t*>(sqlite3_column_blob(stmt_, column));
  const int size = sqlite3_column_bytes(stmt_, column);
  return data ? std::vector<uint8_t>(data, data + size) : std::vector<uint8_t>();
}

bool SqliteStatement::ColumnIsNull(int column) const {
  return sqlite3_column_type(stmt_, column) == SQLITE_NULL;
}

namespace {

/// Prefixes every error about a file with its name, so that a start-up error says which file.
absl::Status NamingFile(const std::string& path, const absl::Status& status) {
  if (status.ok()) return status;
  return absl::Status(status.code(), absl::StrCat("database '", path, "': ", status.message()));
}

}  // namespace

absl::StatusOr<int64_t> SqliteDatabase::QueryInt(std::string_view sql) {
  ASSIGN_OR_RETURN(SqlStatement stmt, Prepare(sql));
  ASSIGN_OR_RETURN(bool row, stmt.Step());
  if (!row) return absl::InternalError(absl::StrCat("'", std::string(sql), "' returned no row"));
  return stmt.ColumnInt(0);
}

absl::StatusOr<std::string> SqliteDatabase::OwnershipProblem(const SqliteOpenOptions& options) {
  if (options.application_id == 0) return std::string();
  // Reading the header also tells a file that is no SQLite database (SQLITE_NOTADB).
  ASSIGN_OR_RETURN(const int64_t id, QueryInt("PRAGMA application_id"));
  if (static_cast<uint32_t>(id) == options.application_id) return std::string();
  ASSIGN_OR_RETURN(const int64_t tables, QueryInt("SELECT COUNT(*) FROM sqlite_master"));
  ASSIGN_OR_RETURN(const int64_t version, QueryInt("PRAGMA user_version"));
  if (id == 0 && tables == 0 && version == 0) return std::string();  // a new, empty file
  if (id == 0 && !options.legacy_table.empty()) {
    ASSIGN_OR_RETURN(SqlStatement legacy,
                     Prepare("SELECT COUNT(*) FROM sqlite_master WHERE type = 'table' AND "
                             "name = ?1"));
    legacy.Bind(1, options.legacy_table);
    ASSIGN_OR_RETURN(bool row, legacy.Step());
    if (row && legacy.ColumnInt(0) == 1 && version > 0) return std::string();
  }
  return absl::StrFormat(
      "not a fleetnav database (application_id 0x%08x, %d tables, user_version %d); refusing to "
      "write to it",
      static_cast<uint32_t>(id), tables, version);
}

absl::StatusOr<std::unique_ptr<SqliteDatabase>> SqliteDatabase::Open(
    const std::string& path, const std::vector<std::string>& migrations,
    const SqliteOpenOptions& options) {
  sqlite3* raw = nullptr;
  const int flags = SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX;
  const int code = sqlite3_open_v2(path.c_str(), &raw, flags, nullptr);
  std::unique_ptr<SqliteDatabase> db(new SqliteDatabase(raw, path));
  if (code != SQLITE_OK) return NamingFile(path, SqliteError(raw, code, "cannot open"));
  sqlite3_busy_timeout(raw, 5000);
  if (sqlite3_db_readonly(raw, "main") == 1) {
    return NamingFile(path, absl::FailedPreconditionError(
                                "the file is read-only (no write permission to it); fleetnavd "
                                "must write its database: fix the permissions or give another "
                                "file"));
  }
  absl::StatusOr<std::string> foreign = db->OwnershipProblem(options);
  if (!foreign.ok()) return NamingFile(path, foreign.status());
  if (!foreign->empty()) return NamingFile(path, absl::FailedPreconditionError(*foreign));
  {
    ASSIGN_OR_RETURN(SqlStatement check, db->Prepare("PRAGMA quick_check(5)"));
    absl::StatusOr<bool> row = check.Step();
    if (!row.ok()) return NamingFile(path, row.status());
    if (*row && check.ColumnText(0) != "ok") {
      return NamingFile(path, absl::DataLossError(absl::StrCat(
                                  "damaged (PRAGMA quick_check: ", check.ColumnText(0),
                                  "); restore a backup or check it with fleetnavd --check-db")));
    }
  }
  absl::Status status = db->Execute("PRAGMA journal_mode=WAL");
  if (status.ok()) {
    status = db->Execute(options.durability == Durability::kFull ? "PRAGMA synchronous=FULL"
                                                                 : "PRAGMA synchronous=NORMAL");
  }
  if (status.ok()) status = db->Execute("PRAGMA foreign_keys=ON");
  if (status.ok() && options.application_id != 0) {
    status = db->Execute(
        absl::StrCat("PRAGMA application_id=", static_cast<int32_t>(options.application_id)));
  }
  if (status.ok()) status = db->Migrate(migrations);
  if (!status.ok()) return NamingFile(path, status);
  return db;
}

absl::StatusOr<SqliteCheckReport> SqliteDatabase::Check(const std::string& path,
                                                        const SqliteOpenOptions& options) {
  sqlite3* raw = nullptr;
  const int code = sqlite3_open_v2(path.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr);
  std::unique_ptr<SqliteDatabase> db(new SqliteDatabase(raw, path));
  if (code != SQLITE_OK) return NamingFile(path, SqliteError(raw, code, "cannot open"));
  SqliteCheckReport report;
  absl::StatusOr<std::string> foreign = db->OwnershipProblem(options);
  if (!foreign.ok()) return NamingFile(path, foreign.status());
  if (!foreign->empty()) report.problems.push_back(*foreign);
  absl::StatusOr<int64_t> version = db->QueryInt("PRAGMA user_version");
  if (!version.ok()) return NamingFile(path, version.status());
  report.schema_version = static_cast<int>(*version);
  absl::StatusOr<SqlStatement> check = db->Prepare("PRAGMA integrity_check(20)");
  if (!check.ok()) return NamingFile(path, check.status());
  while (true) {
    absl::StatusOr<bool> row = check->Step();
    if (!row.ok()) return NamingFile(path, row.status());
    if (!*row) break;
    if (check->ColumnText(0) != "ok") report.problems.push_back(check->ColumnText(0));
  }
  return report;
}

SqliteDatabase::~SqliteDatabase() { sqlite3_close_v2(db_); }

absl::StatusOr<SqlStatement> SqliteDatabase::Prepare(std::string_view sql) {
  sqlite3_stmt* stmt = nullptr;
  const int code =
      sqlite3_prepare_v2(db_, sql.data(), static_cast<int>(sql.size()), &stmt, nullptr);
  if (code != SQLITE_OK)
    return SqliteError(db_, code, absl::StrCat("prepare '", std::string(sql), "'"));
  return SqlStatement(std::make_unique<SqliteStatement>(db_, stmt));
}

int64_t SqliteDatabase::ChangedRows() { return sqlite3_changes64(db_); }

absl::StatusOr<int64_t> SqliteDatabase::NextNumber(std::string_view /*sequence*/,
                                                   std::string_view table,
                                                   std::string_view column) {
  ASSIGN_OR_RETURN(SqlStatement next,
                   Prepare(absl::StrCat("SELECT COALESCE(MAX(", std::string(column),
                                        "), 0) + 1 FROM ", std::string(table))));
  ASSIGN_OR_RETURN(const bool row, next.Step());
  return row ? next.ColumnInt(0) : 1;
}

absl::Status SqliteDatabase::Execute(std::string_view sql) {
  char* error = nullptr;
  const int code = sqlite3_exec(db_, std::string(sql).c_str(), nullptr, nullptr, &error);
  if (code != SQLITE_OK) {
    std::string message = error ? error : sqlite3_errstr(code);
    sqlite3_free(error);
    return SqliteError(nullptr, code, absl::StrCat("exec '", std::string(sql), "': ", message));
  }
  return absl::OkStatus();
}

absl::Status SqliteDatabase::Transaction(const std::function<absl::Status()>& body) {
  // SQLite's own mutex serialises statements; this one keeps a whole transaction together.
  const auto started = std::chrono::steady_clock::now();
  sqlite3_mutex* mutex = sqlite3_db_mutex(db_);
  sqlite3_mutex_enter(mutex);
  absl::Status status = Execute("BEGIN IMMEDIATE");
  if (status.ok()) {
    status = body();
    if (status.ok()) {
      status = Execute("COMMIT");
      if (!status.ok()) (void)Execute("ROLLBACK");
    } else {
      (void)Execute("ROLLBACK");
    }
  }
  sqlite3_mutex_leave(mutex);
  if (status.ok() && transaction_observer_) {
    transaction_observer_(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
  }
  return status;
}

int SqliteDatabase::user_version() {
  auto stmt = Prepare("PRAGMA user_version");
  if (!stmt.ok()) return -1;
  auto row = stmt->Step();
  return (row.ok() && *row) ? static_cast<int>(stmt->ColumnInt(0)) : -1;
}

absl::Status SqliteDatabase::Migrate(const std::vector<std::string>& migrations) {
  const int current = user_version();
  if (current < 0) return absl::InternalError("cannot read PRAGMA user_version");
  if (current > static_cast<int>(migrations.size())) {
    return absl::FailedPreconditionError(absl::StrCat(
        "database schema version ", current, " is newer than this binary's ", migrations.size()));
  }
  for (int version = current; version < static_cast<int>(migrations.size()); ++version) {
    RETURN_IF_ERROR(Transaction([&]() -> absl::Status {
      RETURN_IF_ERROR(Execute(migrations[version]));
      return Execute(absl::StrCat("PRAGMA user_version=", version + 1));
    }));
  }
  return absl::OkStatus();
}

}  // namespace fleetnav::storage
