#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/zone.hpp"

namespace fleetnav::storage {

struct StoredZoneSet {
  ZoneSet zones;
  uint32_t version = 0;
  int64_t created_unix_ms = 0;
};

/// Versioned zone sets (no-go, speed-limit, one-at-a-time), one series per map (versions 1, 2,
/// …), beside the map's marker sets. Thread-safe; a Put stores a whole set or nothing.
class ZoneSetRepository {
 public:
  virtual ~ZoneSetRepository() = default;
  virtual absl::StatusOr<uint32_t> PutZoneSet(const ZoneSet& zones, int64_t created_unix_ms) = 0;
  /// version 0 reads the latest; NotFound names the map (and version).
  virtual absl::StatusOr<StoredZoneSet> GetZoneSet(const std::string& map_id, uint32_t version) = 0;
  /// The latest version of every map's zone set, by map id.
  virtual absl::StatusOr<std::vector<StoredZoneSet>> ListZoneSets() = 0;
  /// Deletes every version of the map's zone set (a new one starts again at 1); NotFound names
  /// the map.
  virtual absl::Status DeleteZoneSet(const std::string& map_id) = 0;
};

}  // namespace fleetnav::storage
