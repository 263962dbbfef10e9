#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"
#include "fleetnav/core/clock.hpp"
#include "fleetnav/core/robot_state.hpp"

namespace fleetnav::server {

struct FleetRegistryParams {
  /// A connected robot with no telemetry for this long is shown as stale.
  double stale_after_s = 2.0;
  absl::Status Validate() const;
};

/// The live table of robots: who is connected, their latest telemetry and connection state.
/// Connection rule: a second connection with the same robot id replaces the first; the first
/// session's later telemetry is refused with FailedPrecondition so that its stream ends.
/// Thread-safe; every method takes the internal mutex briefly and never blocks on I/O.
class FleetRegistry {
 public:
  FleetRegistry(const Clock* clock, FleetRegistryParams params);

  /// Registers a connection and returns its session id.
  uint64_t Connect(const RobotIdentity& identity);
  /// Accepts telemetry from a live session. NotFound for an unknown robot,
  /// FailedPrecondition for a replaced session.
  absl::Status RecordTelemetry(const std::string& robot_id, uint64_t session,
                               const Telemetry& telemetry);
  /// OK when `session` is the robot's current stream: NotFound for an unknown robot,
  /// FailedPrecondition for a replaced session. Every message of an agent stream is checked.
  absl::Status CheckSession(const std::string& robot_id, uint64_t session) const;
  /// Marks the robot offline if `session` is still its current one; returns whether it was.
  bool Disconnect(const std::string& robot_id, uint64_t session);

  /// Removes an offline robot that holds no job. NotFound for an unknown robot,
  /// FailedPrecondition naming why for one that is connected or holds a job.
  absl::Status Forget(const std::string& robot_id);
  /// Ids of robots offline for longer than `offline_for_s` and holding no job, ordered.
  std::vector<std::string> OfflineLongerThan(double offline_for_s) const;
  /// Grows whenever a robot is removed; watchers compare it to learn of removals.
  uint64_t removals() const;
  /// The revision of the latest change.
  uint64_t revision() const;
  /// Bumps the revision of robots that went stale since the last call, so that a robot falling
  /// silent is a change like any other. The server calls it on every dispatcher pass.
  void RefreshStale();
  /// Called after every change (any thread, under the registry's lock: it must only signal).
  void SetChangeListener(std::function<void()> listener);

  /// Adds a robot known from the store as offline (after a restart); no-op if present.
  void RestoreOffline(const RobotIdentity& identity);
  /// Records the job a robot is working on (empty: idle).
  void SetCurrentJob(const std::string& robot_id, const std::string& job_id);
  /// Records why traffic coordination holds the robot (empty: not held).
  void SetTrafficWait(const std::string& robot_id, const std::string& reason);

  absl::StatusOr<RobotRecord> Get(const std::string& robot_id) const;
  /// Every robot, ordered by id, with stale state computed at the current time.
  std::vector<RobotRecord> Snapshot() const;
  /// Robots that are online (not stale), hold no job and satisfy `wanted`, ordered by id. Only
  /// those are copied, so a caller that wants few robots of a large fleet pays little; `wanted`
  /// runs under the registry's reader lock and must not call back into the registry.
  std::vector<RobotRecord> IdleOnline(const std::function<bool(const RobotRecord&)>& wanted) const;
  /// What the connected robots can run between them (the union of their capabilities).
  std::set<std::string> OnlineCapabilities() const;
  /// What the robots that have ever connected (online, stale or offline) can run between them.
  std::set<std::string> KnownCapabilities() const;
  /// Robots whose revision is greater than `after_revision`; sets *latest_revision.
  std::vector<RobotRecord> ChangedSince(uint64_t after_revision, uint64_t* latest_revision) const;

 private:
  struct Entry {
    RobotRecord record;
    uint64_t session = 0;
    int64_t offline_since_ns = 0;  ///< server clock; when it went (or was restored) offline
    bool shown_stale = false;      ///< RefreshStale has published this robot as stale
  };
  /// Increments the revision and tells the listener.
  uint64_t NextRevision() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  RobotRecord WithConnectionState(const Entry& entry) const ABSL_SHARED_LOCKS_REQUIRED(mutex_);
  Entry* Find(const std::string& robot_id) ABSL_SHARED_LOCKS_REQUIRED(mutex_);
  const Entry* Find(const std::string& robot_id) const ABSL_SHARED_LOCKS_REQUIRED(mutex_);
  absl::Status CheckSessionLocked(const std::string& robot_id, uint64_t session) const
      ABSL_SHARED_LOCKS_REQUIRED(mutex_);
  Entry& Insert(const std::string& robot_id) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);

  const Clock* clock_;
  const FleetRegistryParams params_;
  mutable absl::Mutex mutex_;
  std::map<std::string, Entry> robots_ ABSL_GUARDED_BY(mutex_);  ///< ordered views
  /// The same entries by hash, for the per-message lookups (a std::map lookup by id was 7 % of
  /// the server's time at 50,000 messages/s). Forget() erases from both under the lock.
  absl::flat_hash_map<std::string, Entry*> index_ ABSL_GUARDED_BY(mutex_);
  uint64_t next_session_ ABSL_GUARDED_BY(mutex_) = 1;
  uint64_t revision_ ABSL_GUARDED_BY(mutex_) = 0;
  uint64_t removals_ ABSL_GUARDED_BY(mutex_) = 0;
  std::function<void()> listener_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace fleetnav::server
