#pragma once

#include <string>

#include "absl/status/status.h"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/storage/sql/sql_database.hpp"

namespace fleetnav::storage {

/// Runs `delete_sql` (one `?`, bound to `key`) in a transaction: NotFound("`what` not found")
/// when it deleted no row, so a delete of something absent says so and changes nothing.
inline absl::Status DeleteRowsOrNotFound(SqlDatabase* db, const char* delete_sql,
                                         const std::string& key, const std::string& what) {
  return db->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(SqlStatement remove, db->Prepare(delete_sql));
    remove.Bind(1, key);
    RETURN_IF_ERROR(remove.Run());
    if (db->ChangedRows() == 0) return absl::NotFoundError(what + " not found");
    return absl::OkStatus();
  });
}

}  // namespace fleetnav::storage
