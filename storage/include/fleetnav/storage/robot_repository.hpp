#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/statusor.h"

namespace fleetnav::storage {

/// What the store keeps of a robot that has connected: enough to list it after a restart.
/// Its full model comes back with its next hello; until then the kind's preset stands in.
struct StoredRobot {
  std::string robot_id;
  std::string kind_name;
  std::vector<std::string> capabilities;
  std::string software_version;
  int64_t last_seen_unix_ms = 0;
};

/// The robots the server has seen. Thread-safe.
class RobotRepository {
 public:
  virtual ~RobotRepository() = default;
  virtual absl::Status UpsertRobot(const StoredRobot& robot) = 0;
  /// Every robot, ordered by id.
  virtual absl::StatusOr<std::vector<StoredRobot>> ListRobots() = 0;
  /// Forgets the robot; NotFound when it is not stored.
  virtual absl::Status DeleteRobot(const std::string& robot_id) = 0;
};

}  // namespace fleetnav::storage
