#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "absl/status/status.h"
#include "fleetnav/server/robots/fleet_registry.hpp"
#include "fleetnav/storage/pose_history_repository.hpp"

namespace fleetnav::server {

struct PoseHistoryParams {
  double period_s = 1.0;       ///< one sample per robot per period (when it reported)
  double retention_s = 86400;  ///< samples older than this are dropped
  absl::Status Validate() const;
};

/// Down-samples the registry's live poses into the pose history: each RecordOnce() stores, in
/// one transaction, the latest pose of every robot that reported since the last call, and drops
/// samples past the retention. Called by one thread (the server's housekeeping loop).
class PoseHistoryRecorder {
 public:
  PoseHistoryRecorder(const FleetRegistry* registry, storage::PoseHistoryRepository* history,
                      PoseHistoryParams params)
      : registry_(registry), history_(history), params_(params) {}

  /// Returns how many samples were stored.
  absl::StatusOr<int> RecordOnce(int64_t now_unix_ms);
  const PoseHistoryParams& params() const { return params_; }

 private:
  const FleetRegistry* registry_;
  storage::PoseHistoryRepository* history_;
  PoseHistoryParams params_;
  std::map<std::string, uint64_t> recorded_count_;  ///< telemetry_count at the last sample
  int64_t last_prune_unix_ms_ = 0;
};

}  // namespace fleetnav::server
