#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/storage/postgres/pg_database.hpp"

namespace fleetnav::storage {

/// Class id of the advisory locks on site leases (the two-key lock space, apart from the
/// one-key locks of LockKey): "FNLS".
inline constexpr int32_t kSiteLeaseLockClass = 0x464E4C53;

/// Site names are letters, digits, '_', '-' and '.', 1 to 64 of them (InvalidArgument otherwise).
absl::Status ValidateSiteName(std::string_view site);

/// A site's lease as stored: who leads it, where the other replicas reach the leader, the
/// epoch (the fencing token, one more with every new holder) and whether it has run out.
struct SiteLease {
  std::string holder;
  std::string address;
  int64_t epoch = 0;
  bool expired = false;
};

/// The leases that make one fleetnavd replica the leader of a site, in the table
/// `site_leases` of a PostgreSQL database the replicas share. Times are the database server's
/// (clock_timestamp()), so the replicas' clocks need not agree. A lease is taken only when
/// there is none or it ran out, under the site's lease lock held exclusively: that waits for
/// every transaction the old leader's fenced store has in flight (PgFence holds the same lock
/// shared) and raises the epoch, so none of the old leader's writes can land afterwards.
/// Thread-safe as its PgDatabase.
class PgSiteLeases {
 public:
  PgSiteLeases(PgDatabase* db, double ttl_s)
      : db_(db), ttl_ms_(static_cast<int64_t>(ttl_s * 1e3)) {}

  /// The site's lease, or nullopt when no replica ever led it.
  absl::StatusOr<std::optional<SiteLease>> Current(const std::string& site);
  /// Takes the lease for `holder` if it is free or ran out, for ttl_s from now; returns the new
  /// epoch, or nullopt when another holder's lease is still running.
  absl::StatusOr<std::optional<int64_t>> TryAcquire(const std::string& site,
                                                    const std::string& holder,
                                                    const std::string& address);
  /// Extends the holder's lease by ttl_s from now. FailedPrecondition when the lease has
  /// another holder or epoch (it was lost); UNAVAILABLE when the database cannot be reached.
  absl::Status Renew(const std::string& site, const std::string& holder, int64_t epoch);
  /// Ends the holder's lease now, so that another replica takes over without waiting
  /// (a leader shutting down); FailedPrecondition as Renew.
  absl::Status Release(const std::string& site, const std::string& holder, int64_t epoch);
  /// Records where the other replicas reach the holder; FailedPrecondition as Renew.
  absl::Status SetAddress(const std::string& site, const std::string& holder, int64_t epoch,
                          const std::string& address);

 private:
  /// Runs `update` (site, holder, epoch bound last, after `first`) and requires one row changed.
  absl::Status UpdateHeld(const std::string& sql, const std::function<void(SqlStatement&)>& first,
                          const std::string& site, const std::string& holder, int64_t epoch);

  PgDatabase* db_;
  int64_t ttl_ms_;
};

}  // namespace fleetnav::storage
