#pragma once

#include <cstdint>
#include <string>

#include "absl/status/statusor.h"
#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/storage/sql/sql_database.hpp"

namespace fleetnav::storage {

/// The next version of a (key, version) series in `table`, inside the current transaction
/// (the key is locked first, so two writers never take the same version).
inline absl::StatusOr<uint32_t> NextVersion(SqlDatabase* db, const std::string& table,
                                            const std::string& key_column, const std::string& key) {
  RETURN_IF_ERROR(db->LockKey(absl::StrCat(table, ":", key)));
  ASSIGN_OR_RETURN(SqlStatement latest,
                   db->Prepare(absl::StrCat("SELECT COALESCE(MAX(version), 0) FROM ", table,
                                            " WHERE ", key_column, " = ?")));
  latest.Bind(1, key);
  ASSIGN_OR_RETURN(bool has_row, latest.Step());
  return static_cast<uint32_t>(has_row ? latest.ColumnInt(0) + 1 : 1);
}

/// " has no version N" for a NotFound message, or nothing for version 0 (the latest).
inline std::string VersionText(uint32_t version) {
  return version == 0 ? "" : absl::StrCat(" has no version ", version);
}

}  // namespace fleetnav::storage
