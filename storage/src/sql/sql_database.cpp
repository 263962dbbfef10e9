#include "fleetnav/storage/sql/sql_database.hpp"

#include "fleetnav/core/status_macros.hpp"

namespace fleetnav::storage {

absl::Status SqlStatement::Run() {
  while (true) {
    ASSIGN_OR_RETURN(bool row, Step());
    if (!row) return absl::OkStatus();
  }
}

}  // namespace fleetnav::storage
