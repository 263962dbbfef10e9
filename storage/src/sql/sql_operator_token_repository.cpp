#include "absl/strings/str_cat.h"
#include "delete_rows_internal.hpp"
#include "fleetnav/core/echo_input.hpp"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/storage/sql/sql_fleet_repositories.hpp"

namespace fleetnav::storage {

absl::Status SqlOperatorTokenRepository::InsertToken(const StoredOperatorToken& stored) {
  return db_->Transaction([&]() -> absl::Status {
    // Name and hash are unique; ON CONFLICT DO NOTHING then the changed rows tell a taken one
    // from a stored one without parsing an engine's error text.
    ASSIGN_OR_RETURN(SqlStatement insert,
                     db_->Prepare("INSERT INTO operator_tokens (name, role_name, sha256_hex, "
                                  "created_unix_ms) VALUES (?, ?, ?, ?) ON CONFLICT DO NOTHING"));
    const std::string role_name(RoleName(stored.token.role));
    insert.Bind(1, stored.token.name)
        .Bind(2, role_name)
        .Bind(3, stored.token.sha256_hex)
        .Bind(4, stored.created_unix_ms);
    RETURN_IF_ERROR(insert.Run());
    if (db_->ChangedRows() == 0) {
      return absl::AlreadyExistsError(absl::StrCat("a token named '", EchoInput(stored.token.name),
                                                   "' or with the same secret exists"));
    }
    return absl::OkStatus();
  });
}

absl::StatusOr<std::vector<StoredOperatorToken>> SqlOperatorTokenRepository::ListTokens() {
  std::vector<StoredOperatorToken> out;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(SqlStatement query,
                     db_->Prepare("SELECT name, role_name, sha256_hex, created_unix_ms FROM "
                                  "operator_tokens ORDER BY name"));
    while (true) {
      ASSIGN_OR_RETURN(bool has_row, query.Step());
      if (!has_row) break;
      ASSIGN_OR_RETURN(const Role role, ParseRole(query.ColumnText(1)));
      out.push_back({{query.ColumnText(0), role, query.ColumnText(2)}, query.ColumnInt(3)});
    }
    return absl::OkStatus();
  }));
  return out;
}

absl::Status SqlOperatorTokenRepository::DeleteToken(const std::string& name) {
  return DeleteRowsOrNotFound(db_, "DELETE FROM operator_tokens WHERE name = ?", name,
                              absl::StrCat("token '", EchoInput(name), "'"));
}

}  // namespace fleetnav::storage
