#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fleetnav/core/zone.hpp"

namespace fleetnav {

/// An operator's stop (issue 39): every robot of the fleet (`zone` empty), or every robot inside
/// one zone of a map or about to enter it, is commanded to speed 0 until someone clears it. The
/// zone's outline is kept with the stop, so a stop holds as it was made whatever later zone
/// versions say. Not a safety-rated emergency stop: it travels the same network as every other
/// command. Value type.
struct RobotStop {
  std::string map_id;  ///< empty for the whole fleet
  std::string zone;    ///< empty for the whole fleet
  Polygon2 polygon_in_map;
  std::string reason;
  int64_t created_unix_ms = 0;

  bool whole_fleet() const { return zone.empty(); }
  /// "the whole fleet", or "zone 'pen' of map 'barn'".
  std::string Describe() const;
};

/// Whether a robot at `center` (m, map frame) whose reach — footprint, grown uncertainty and
/// braking distance — is `reach_m` must stand for one of `stops` on map `map_id`: a
/// whole-fleet stop, or a zone stop of that map whose zone the reach touches. The first that
/// applies; nullptr when none does.
const RobotStop* ApplyingStop(const std::vector<RobotStop>& stops, const std::string& map_id,
                              const Eigen::Vector2d& center, double reach_m);

}  // namespace fleetnav
