#pragma once

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/robot_stop.hpp"

namespace fleetnav::storage {

/// The operators' stops in force, one per scope (the whole fleet, or a map's zone), kept until
/// cleared so that they hold through a restart of fleetnavd and a failover of its replicas.
/// Thread-safe.
class StopRepository {
 public:
  virtual ~StopRepository() = default;
  /// Stores the stop; a stop of the same scope already in force is kept as it is
  /// (AlreadyExists naming the scope).
  virtual absl::Status PutStop(const RobotStop& stop) = 0;
  /// Clears the stop of the scope (zone "" and map "": the whole fleet); NotFound naming it.
  virtual absl::Status DeleteStop(const std::string& map_id, const std::string& zone) = 0;
  /// Every stop in force, oldest first.
  virtual absl::StatusOr<std::vector<RobotStop>> ListStops() = 0;
};

}  // namespace fleetnav::storage
