#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "absl/status/statusor.h"
#include "fleetnav/core/occupancy_grid.hpp"
#include "fleetnav/core/stripe_marker.hpp"
#include "fleetnav/core/zone.hpp"

namespace fleetnav::agent {

/// What the robot knows of a site for one job: the map and marker set at the exact versions its
/// route was validated against.
struct SiteData {
  std::string map_id;
  uint32_t map_version = 0;
  uint32_t marker_set_version = 0;  ///< 0: the map has no marker set
  std::shared_ptr<const OccupancyGrid> map;
  std::optional<MarkerSet> markers;
};

/// Where the agent gets a job's map and marker set (fleetnavd in job mode). Called from the
/// control loop between jobs; may block for a round trip.
class SiteSource {
 public:
  virtual ~SiteSource() = default;
  /// NotFound for a map or version the source does not have.
  virtual absl::StatusOr<SiteData> Load(const std::string& map_id, uint32_t map_version,
                                        uint32_t marker_set_version) = 0;
  /// The map's zones at `zone_set_version` (> 0). A source that knows no zones has none.
  virtual absl::StatusOr<std::optional<ZoneSet>> LoadZones(const std::string& map_id,
                                                           uint32_t zone_set_version) {
    (void)map_id;
    (void)zone_set_version;
    return std::nullopt;
  }
};

}  // namespace fleetnav::agent
