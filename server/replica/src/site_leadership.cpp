#include "fleetnav/server/replica/site_leadership.hpp"

#include <unistd.h>

#include <random>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/time/time.h"

namespace fleetnav::server {

absl::Status SiteLeadershipParams::Validate() const {
  if (absl::Status site_ok = storage::ValidateSiteName(site); !site_ok.ok()) return site_ok;
  if (!(lease_ttl_s >= 0.3 && lease_ttl_s <= 60.0)) {
    return absl::InvalidArgumentError(
        absl::StrCat("lease_ttl_s: must be in [0.3, 60], got ", lease_ttl_s));
  }
  if (!(renew_period_s > 0.0 && renew_period_s * 3.0 <= lease_ttl_s)) {
    return absl::InvalidArgumentError(absl::StrCat(
        "renew_period_s: must be > 0 and at most a third of lease_ttl_s, got ", renew_period_s));
  }
  if (!(poll_period_s > 0.0 && poll_period_s <= lease_ttl_s)) {
    return absl::InvalidArgumentError(
        absl::StrCat("poll_period_s: must be in (0, lease_ttl_s], got ", poll_period_s));
  }
  return absl::OkStatus();
}

std::string NewLeaseHolderId() {
  char host[256] = {};
  if (gethostname(host, sizeof(host) - 1) != 0) host[0] = '\0';
  std::random_device random;
  return absl::StrFormat("%s:%d:%08x", host, getpid(), random());
}

void SiteLeadership::Start() {
  thread_ = std::thread([this] { Run(); });
}

void SiteLeadership::Stop() {
  if (!stop_.HasBeenNotified()) stop_.Notify();
  if (thread_.joinable()) thread_.join();
}

absl::Status SiteLeadership::Publish(int64_t epoch, const std::string& address) {
  return leases_->SetAddress(params_.site, holder_, epoch, address);
}

std::optional<SiteLeadership::Won> SiteLeadership::Follow(storage::SiteLease* seen) {
  absl::StatusOr<std::optional<storage::SiteLease>> lease = leases_->Current(params_.site);
  if (!lease.ok()) return std::nullopt;  // the database is away: keep following, try again
  if (!lease->has_value() || (*lease)->expired) {
    const int64_t sent_ns = clock_->NowNs();
    absl::StatusOr<std::optional<int64_t>> epoch =
        leases_->TryAcquire(params_.site, holder_, /*address=*/"");
    if (epoch.ok() && epoch->has_value()) {
      events_.elected(**epoch);
      return Won{**epoch, sent_ns};
    }
    lease = leases_->Current(params_.site);
    if (!lease.ok() || !lease->has_value()) return std::nullopt;
  }
  const storage::SiteLease& current = **lease;
  if (current.epoch != seen->epoch || current.address != seen->address) {
    *seen = current;
    events_.leader_changed(current);
  }
  return std::nullopt;
}

void SiteLeadership::Run() {
  storage::SiteLease seen;
  std::optional<Won> won;
  while (!(won = Follow(&seen))) {
    if (stop_.WaitForNotificationWithTimeout(absl::Seconds(params_.poll_period_s))) return;
  }
  // Lead: the lease counts from before the acquiring or renewing statement was sent, so this
  // replica stops leading no later than the database lets another take over.
  const int64_t ttl_ns = static_cast<int64_t>(params_.lease_ttl_s * 1e9);
  int64_t valid_until_ns = won->sent_ns + ttl_ns;
  while (!stop_.WaitForNotificationWithTimeout(absl::Seconds(params_.renew_period_s))) {
    const int64_t sent_ns = clock_->NowNs();
    const absl::Status renewed = leases_->Renew(params_.site, holder_, won->epoch);
    if (renewed.ok()) {
      valid_until_ns = sent_ns + ttl_ns;
      continue;
    }
    if (renewed.code() == absl::StatusCode::kFailedPrecondition) {
      events_.lost(std::string(renewed.message()));
      return;
    }
    if (clock_->NowNs() >= valid_until_ns) {
      events_.lost(absl::StrCat("the lease of site '", params_.site,
                                "' could not be renewed within ", params_.lease_ttl_s,
                                " s: ", renewed.message()));
      return;
    }
  }
}

}  // namespace fleetnav::server
