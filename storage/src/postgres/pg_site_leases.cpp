#include "fleetnav/storage/postgres/pg_site_leases.hpp"

#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"

namespace fleetnav::storage {

absl::Status ValidateSiteName(std::string_view site) {
  if (site.empty() || site.size() > 64) {
    return absl::InvalidArgumentError(
        absl::StrCat("site name: 1 to 64 characters, got ", site.size()));
  }
  for (const char c : site) {
    const bool allowed = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                         (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '.';
    if (!allowed) {
      return absl::InvalidArgumentError(
          absl::StrCat("site name '", std::string(site), "': only letters, digits, '_', '-', '.'"));
    }
  }
  return absl::OkStatus();
}

absl::StatusOr<std::optional<SiteLease>> PgSiteLeases::Current(const std::string& site) {
  std::optional<SiteLease> lease;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    lease.reset();
    ASSIGN_OR_RETURN(SqlStatement read,
                     db_->Prepare("SELECT holder, address, epoch, "
                                  "CASE WHEN expires_at < clock_timestamp() THEN 1 ELSE 0 END "
                                  "FROM site_leases WHERE site = ?"));
    read.Bind(1, site);
    ASSIGN_OR_RETURN(const bool row, read.Step());
    if (row) {
      lease = SiteLease{read.ColumnText(0), read.ColumnText(1), read.ColumnInt(2),
                        read.ColumnInt(3) == 1};
    }
    return absl::OkStatus();
  }));
  return lease;
}

absl::StatusOr<std::optional<int64_t>> PgSiteLeases::TryAcquire(const std::string& site,
                                                                const std::string& holder,
                                                                const std::string& address) {
  RETURN_IF_ERROR(ValidateSiteName(site));
  std::optional<int64_t> epoch;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    epoch.reset();
    // Waits for the old leader's fenced transactions still running; later ones see the new
    // epoch and fail.
    ASSIGN_OR_RETURN(SqlStatement lock,
                     db_->Prepare(absl::StrCat("SELECT pg_advisory_xact_lock(", kSiteLeaseLockClass,
                                               ", hashtext(?))")));
    lock.Bind(1, site);
    RETURN_IF_ERROR(lock.Run());
    ASSIGN_OR_RETURN(
        SqlStatement take,
        db_->Prepare(
            "INSERT INTO site_leases (site, holder, address, epoch, expires_at) "
            "VALUES (?, ?, ?, 1, clock_timestamp() + CAST(? AS BIGINT) * interval '1 millisecond') "
            "ON CONFLICT (site) DO UPDATE SET holder = excluded.holder, "
            "address = excluded.address, epoch = site_leases.epoch + 1, "
            "expires_at = excluded.expires_at "
            "WHERE site_leases.expires_at < clock_timestamp() RETURNING epoch"));
    take.Bind(1, site);
    take.Bind(2, holder);
    take.Bind(3, address);
    take.Bind(4, ttl_ms_);
    ASSIGN_OR_RETURN(const bool row, take.Step());
    if (row) epoch = take.ColumnInt(0);
    return absl::OkStatus();
  }));
  return epoch;
}

absl::Status PgSiteLeases::Renew(const std::string& site, const std::string& holder,
                                 int64_t epoch) {
  return UpdateHeld(
      "UPDATE site_leases SET expires_at = clock_timestamp() + CAST(? AS BIGINT) * interval "
      "'1 millisecond' WHERE site = ? AND holder = ? AND epoch = ?",
      [this](SqlStatement& update) { update.Bind(1, ttl_ms_); }, site, holder, epoch);
}

absl::Status PgSiteLeases::Release(const std::string& site, const std::string& holder,
                                   int64_t epoch) {
  return UpdateHeld(
      "UPDATE site_leases SET expires_at = clock_timestamp() - CAST(? AS BIGINT) * interval "
      "'1 millisecond' WHERE site = ? AND holder = ? AND epoch = ?",
      [](SqlStatement& update) { update.Bind(1, int64_t{1}); }, site, holder, epoch);
}

absl::Status PgSiteLeases::SetAddress(const std::string& site, const std::string& holder,
                                      int64_t epoch, const std::string& address) {
  return UpdateHeld(
      "UPDATE site_leases SET address = ? WHERE site = ? AND holder = ? AND epoch = ?",
      [&address](SqlStatement& update) { update.Bind(1, address); }, site, holder, epoch);
}

absl::Status PgSiteLeases::UpdateHeld(const std::string& sql,
                                      const std::function<void(SqlStatement&)>& first,
                                      const std::string& site, const std::string& holder,
                                      int64_t epoch) {
  bool held = false;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(SqlStatement update, db_->Prepare(sql));
    first(update);
    update.Bind(2, site);
    update.Bind(3, holder);
    update.Bind(4, epoch);
    RETURN_IF_ERROR(update.Run());
    held = db_->ChangedRows() == 1;
    return absl::OkStatus();
  }));
  if (!held) {
    return absl::FailedPreconditionError(
        absl::StrCat("the lease of site '", site, "' at epoch ", epoch, " was taken over"));
  }
  return absl::OkStatus();
}

}  // namespace fleetnav::storage
