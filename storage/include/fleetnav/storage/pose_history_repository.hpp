#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/pose2.hpp"

namespace fleetnav::storage {

struct PoseSample {
  std::string robot_id;
  int64_t unix_ms = 0;   ///< server wall time when recorded
  int64_t stamp_ns = 0;  ///< the robot's own stamp of the telemetry
  Pose2 pose_in_map;
};

/// Down-sampled pose history of every robot (the server records about one sample per robot per
/// second, in one transaction for all robots). Thread-safe.
class PoseHistoryRepository {
 public:
  virtual ~PoseHistoryRepository() = default;
  virtual absl::Status AppendPoses(const std::vector<PoseSample>& samples) = 0;
  /// A robot's samples with unix_ms >= since_unix_ms, oldest first, at most `limit`.
  virtual absl::StatusOr<std::vector<PoseSample>> ListPoses(const std::string& robot_id,
                                                            int64_t since_unix_ms, int limit) = 0;
  /// Drops samples older than before_unix_ms; returns how many.
  virtual absl::StatusOr<int64_t> PruneBefore(int64_t before_unix_ms) = 0;
};

}  // namespace fleetnav::storage
