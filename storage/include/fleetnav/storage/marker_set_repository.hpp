#pragma once

#include <cstdint>
#include <string>

#include "absl/status/statusor.h"
#include "fleetnav/core/stripe_marker.hpp"

namespace fleetnav::storage {

struct StoredMarkerSet {
  MarkerSet markers;
  uint32_t version = 0;
  int64_t created_unix_ms = 0;
};

/// Versioned stripe-marker sets, one series per map (versions 1, 2, …). Thread-safe; a Put
/// stores a whole set or nothing.
class MarkerSetRepository {
 public:
  virtual ~MarkerSetRepository() = default;
  virtual absl::StatusOr<uint32_t> PutMarkerSet(const MarkerSet& markers,
                                                int64_t created_unix_ms) = 0;
  /// version 0 reads the latest; NotFound names the map (and version).
  virtual absl::StatusOr<StoredMarkerSet> GetMarkerSet(const std::string& map_id,
                                                       uint32_t version) = 0;
  /// Deletes every version of the map's marker set (a new one starts again at 1); NotFound
  /// names the map.
  virtual absl::Status DeleteMarkerSet(const std::string& map_id) = 0;
};

}  // namespace fleetnav::storage
