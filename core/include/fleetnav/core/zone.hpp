#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/core/occupancy_grid.hpp"

namespace fleetnav {

/// What a zone asks of the robots: never enter it (`kNoGo`), drive no faster than its limit
/// inside it (`kSpeedLimit`), or at most `capacity` robots inside it at once (`kOneAtATime`).
enum class ZoneKind { kNoGo, kSpeedLimit, kOneAtATime };

std::string_view ZoneKindName(ZoneKind kind);
/// "no_go", "speed_limit" or "one_at_a_time"; InvalidArgument naming the accepted names.
absl::StatusOr<ZoneKind> ParseZoneKind(std::string_view name);

/// A simple polygon in the map frame: its vertices in order (either winding), the closing edge
/// from the last vertex back to the first implied. Free functions below answer containment,
/// distance and crossing; they assume a polygon that ValidatePolygon accepted.
using Polygon2 = std::vector<Eigen::Vector2d>;

/// InvalidArgument naming `field` when the polygon has fewer than 3 vertices, a non-finite
/// vertex, two consecutive vertices closer than 1 mm, an area under 1e-4 m² (degenerate), or
/// two edges that cross or touch other than at their shared vertex (self-intersecting).
absl::Status ValidatePolygon(const Polygon2& polygon, std::string_view field);
/// True when the point lies inside the polygon or on its boundary.
bool PolygonContains(const Polygon2& polygon, const Eigen::Vector2d& point);
/// Distance from the point to the polygon's boundary (0 on it); see PolygonContains for the side.
double DistanceToPolygonBoundary(const Polygon2& polygon, const Eigen::Vector2d& point);
/// True when a disc of `radius_m` about `center` overlaps the polygon (inside or within reach).
bool DiscTouchesPolygon(const Polygon2& polygon, const Eigen::Vector2d& center, double radius_m);
/// True when the segment a→b, swept by a disc of `radius_m`, overlaps the polygon.
bool SegmentTouchesPolygon(const Polygon2& polygon, const Eigen::Vector2d& a,
                           const Eigen::Vector2d& b, double radius_m);
/// Signed area (counter-clockwise positive), m².
double PolygonArea(const Polygon2& polygon);

/// An area of a map with a rule (issue 39): a name unique on its map, its kind, its outline,
/// and the kind's one figure — the speed limit in m/s of a speed-limit zone (> 0), the number
/// of robots a one-at-a-time zone admits at once (≥ 1). Value type.
struct Zone {
  std::string name;
  ZoneKind kind = ZoneKind::kNoGo;
  Polygon2 polygon_in_map;
  double speed_limit_mps = 0.0;  ///< kSpeedLimit only
  int capacity = 1;              ///< kOneAtATime only
};

/// The zones of one map: the site layer stored, versioned, beside its map and marker set.
/// Validate() checks names (1-64 of [A-Za-z0-9_.-], unique), polygons (ValidatePolygon) and
/// each kind's figure, naming the field (`zones[i].polygon`, `zones[i].speed_limit`, …). An
/// empty set is valid: it lifts every rule. Value type.
struct ZoneSet {
  std::string map_id;
  std::vector<Zone> zones;

  absl::Status Validate() const;
  const Zone* Find(std::string_view name) const;
  /// Whether some zone is of `kind`.
  bool HasKind(ZoneKind kind) const;
  /// Zones of `kind` that a disc of `radius_m` about `point_in_map` overlaps.
  std::vector<const Zone*> Touching(ZoneKind kind, const Eigen::Vector2d& point_in_map,
                                    double radius_m) const;
  /// The lowest limit of the speed-limit zones a disc of `radius_m` about the point overlaps;
  /// nullopt when none does.
  std::optional<double> SpeedLimitAt(const Eigen::Vector2d& point_in_map, double radius_m) const;
};

/// InvalidArgument naming `zones[i].polygon[j]` for a vertex outside the map's extent.
absl::Status CheckZonesOnMap(const ZoneSet& zones, const OccupancyGrid& grid);

/// `grid` with every cell that a no-go zone of `zones` overlaps marked occupied (100): the map
/// planners plan on, so that their paths, inflated by the footprint, keep the robot out of the
/// zones. Localization keeps the true map (a zone is no wall). Cells outside every no-go zone
/// keep their value.
OccupancyGrid WithNoGoZonesOccupied(const OccupancyGrid& grid, const ZoneSet& zones);
/// The grid planners plan on: `grid` itself when `zones` is null or holds no no-go zone (no
/// copy), else WithNoGoZonesOccupied, kept in `storage`.
const OccupancyGrid& PlanningGrid(const OccupancyGrid& grid, const ZoneSet* zones,
                                  std::optional<OccupancyGrid>& storage);

/// Zone YAML:
///   map: barn                       # optional
///   zones:
///     - name: pen-3
///       kind: no_go                 # no_go | speed_limit | one_at_a_time
///       polygon: [[1.0, 2.0], [4.0, 2.0], [4.0, 5.0]]   # metres, map frame
///       speed_limit: 0.3            # m/s; speed_limit zones only
///       capacity: 1                 # one_at_a_time zones only (default 1)
/// Parsing validates (ZoneSet::Validate) and refuses unknown keys and a figure on the wrong
/// kind, naming the field.
absl::StatusOr<ZoneSet> ParseZoneSetYaml(std::string_view yaml_text);
std::string ZoneSetToYaml(const ZoneSet& zones);
absl::StatusOr<ZoneSet> LoadZoneSet(const std::string& path);
absl::Status SaveZoneSet(const ZoneSet& zones, const std::string& path);

}  // namespace fleetnav
