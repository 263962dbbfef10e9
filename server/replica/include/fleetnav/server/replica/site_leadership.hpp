#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <thread>

#include "absl/status/status.h"
#include "absl/synchronization/notification.h"
#include "fleetnav/core/clock.hpp"
#include "fleetnav/storage/postgres/pg_site_leases.hpp"

namespace fleetnav::server {

struct SiteLeadershipParams {
  std::string site = "default";
  /// A leader that has not renewed its lease for this long is replaced. Failover takes about
  /// this plus one poll period plus the new leader's start.
  double lease_ttl_s = 2.0;
  /// How often the leader renews (at most a third of the TTL, so one lost renewal is no loss).
  double renew_period_s = 0.5;
  /// How often the other replicas read the lease (to learn the leader, or to take over).
  double poll_period_s = 0.25;
  /// The periods as fleetnavd sets them from its one flag: renew every TTL/4, read every TTL/8.
  static SiteLeadershipParams ForTtl(std::string site, double lease_ttl_s) {
    return {std::move(site), lease_ttl_s, lease_ttl_s / 4.0, lease_ttl_s / 8.0};
  }
  absl::Status Validate() const;
};

/// What SiteLeadership tells its owner, on its own thread; each must return quickly.
struct SiteLeadershipEvents {
  /// This replica now holds the lease at `epoch`: start leading (on another thread) and
  /// Publish the address the other replicas reach the leader at.
  std::function<void(int64_t epoch)> elected;
  /// The lease as other replicas see it changed (new holder, epoch or address).
  std::function<void(const storage::SiteLease& lease)> leader_changed;
  /// This replica led and no longer does (taken over, or not renewed within the TTL): it must
  /// stop acting as leader at once. Called once; the thread then ends.
  std::function<void(const std::string& why)> lost;
};

/// The leader election of one site among fleetnavd replicas sharing a PostgreSQL database: a
/// thread that, while this replica follows, reads the site's lease every poll period, reports
/// its holder and takes it over when there is none or it ran out; and while it leads, renews
/// the lease every renew period. The leader counts its lease from before each renewal was
/// sent (on the injected monotonic clock), so it gives up leading no later than the database
/// lets another replica take over; its store is fenced by the epoch besides (PgFence), so
/// even a leader paused past that point writes nothing afterwards. Start once; Stop joins.
class SiteLeadership {
 public:
  SiteLeadership(storage::PgSiteLeases* leases, const Clock* clock, std::string holder,
                 SiteLeadershipParams params, SiteLeadershipEvents events)
      : leases_(leases),
        clock_(clock),
        holder_(std::move(holder)),
        params_(std::move(params)),
        events_(std::move(events)) {}
  ~SiteLeadership() { Stop(); }
  SiteLeadership(const SiteLeadership&) = delete;
  SiteLeadership& operator=(const SiteLeadership&) = delete;

  void Start();
  void Stop();
  /// Records where the other replicas reach this leader (after its server started).
  absl::Status Publish(int64_t epoch, const std::string& address);
  const std::string& holder() const { return holder_; }

 private:
  /// The epoch this replica won, and when the winning statement was sent.
  struct Won {
    int64_t epoch = 0;
    int64_t sent_ns = 0;
  };
  void Run();
  /// One follower round: reports a lease that differs from `seen` (and records it there), and
  /// takes the lease when it is free or ran out.
  std::optional<Won> Follow(storage::SiteLease* seen);

  storage::PgSiteLeases* leases_;
  const Clock* clock_;
  const std::string holder_;
  const SiteLeadershipParams params_;
  const SiteLeadershipEvents events_;
  absl::Notification stop_;
  std::thread thread_;
};

/// A holder id unique to this process: host name, process id and a random part.
std::string NewLeaseHolderId();

}  // namespace fleetnav::server
