#include "fleetnav/core/zone.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/echo_input.hpp"
#include "fleetnav/core/segment_distance.hpp"
#include "fleetnav/core/status_macros.hpp"
#include "strings_internal.hpp"

namespace fleetnav {
namespace {

constexpr double kMinEdgeM = 1e-3;
constexpr double kMinAreaM2 = 1e-4;

double Cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

int Sign(double value) { return (value > 0.0) - (value < 0.0); }

bool OnSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return std::min(a.x(), b.x()) <= p.x() && p.x() <= std::max(a.x(), b.x()) &&
         std::min(a.y(), b.y()) <= p.y() && p.y() <= std::max(a.y(), b.y());
}

// Segments p1–p2 and q1–q2 share at least one point (touching counts).
bool SegmentsIntersect(const Eigen::Vector2d& p1, const Eigen::Vector2d& p2,
                       const Eigen::Vector2d& q1, const Eigen::Vector2d& q2) {
  const int d1 = Sign(Cross(q1, q2, p1));
  const int d2 = Sign(Cross(q1, q2, p2));
  const int d3 = Sign(Cross(p1, p2, q1));
  const int d4 = Sign(Cross(p1, p2, q2));
  if (d1 * d2 < 0 && d3 * d4 < 0) return true;
  return (d1 == 0 && OnSegment(p1, q1, q2)) || (d2 == 0 && OnSegment(p2, q1, q2)) ||
         (d3 == 0 && OnSegment(q1, p1, p2)) || (d4 == 0 && OnSegment(q2, p1, p2));
}

double SegmentSegmentDistance(const Eigen::Vector2d& p1, const Eigen::Vector2d& p2,
                              const Eigen::Vector2d& q1, const Eigen::Vector2d& q2) {
  if (SegmentsIntersect(p1, p2, q1, q2)) return 0.0;
  return std::min({PointSegmentDistance(p1, q1, q2), PointSegmentDistance(p2, q1, q2),
                   PointSegmentDistance(q1, p1, p2), PointSegmentDistance(q2, p1, p2)});
}

bool IsValidZoneName(const std::string& name) {
  if (name.empty() || name.size() > 64) return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-' || c == '.';
  });
}

}  // namespace

std::string_view ZoneKindName(ZoneKind kind) {
  switch (kind) {
    case ZoneKind::kNoGo:
      return "no_go";
    case ZoneKind::kSpeedLimit:
      return "speed_limit";
    case ZoneKind::kOneAtATime:
      return "one_at_a_time";
  }
  return "unknown";
}

absl::StatusOr<ZoneKind> ParseZoneKind(std::string_view name) {
  for (ZoneKind kind : {ZoneKind::kNoGo, ZoneKind::kSpeedLimit, ZoneKind::kOneAtATime}) {
    if (name == ZoneKindName(kind)) return kind;
  }
  return absl::InvalidArgumentError(absl::StrCat(
      "unknown zone kind '", EchoInput(name), "' (expected no_go, speed_limit or one_at_a_time)"));
}

double PolygonArea(const Polygon2& polygon) {
  double twice_area = 0.0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[(i + 1) % polygon.size()];
    twice_area += a.x() * b.y() - b.x() * a.y();
  }
  return 0.5 * twice_area;
}

absl::Status ValidatePolygon(const Polygon2& polygon, std::string_view field) {
  const absl::string_view where = internal::ToAbsl(field);
  if (polygon.size() < 3) {
    return absl::InvalidArgumentError(
        absl::StrCat(where, ": needs at least 3 vertices, got ", polygon.size()));
  }
  const size_t n = polygon.size();
  for (size_t i = 0; i < n; ++i) {
    if (!polygon[i].allFinite()) {
      return absl::InvalidArgumentError(absl::StrCat(where, "[", i, "]: not a finite point"));
    }
  }
  for (size_t i = 0; i < n; ++i) {
    if ((polygon[(i + 1) % n] - polygon[i]).norm() < kMinEdgeM) {
      return absl::InvalidArgumentError(
          absl::StrCat(where, ": vertices ", i, " and ", (i + 1) % n, " coincide (degenerate)"));
    }
  }
  // Edges i and j (not neighbours) must not meet: O(n²) over a bounded vertex count.
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = i + 1; j < n; ++j) {
      const bool neighbours = j == i + 1 || (i == 0 && j == n - 1);
      if (neighbours) continue;
      if (SegmentsIntersect(polygon[i], polygon[(i + 1) % n], polygon[j], polygon[(j + 1) % n])) {
        return absl::InvalidArgumentError(absl::StrCat(where, ": edges ", i, "-", (i + 1) % n,
                                                       " and ", j, "-", (j + 1) % n,
                                                       " cross (self-intersecting)"));
      }
    }
  }
  if (std::abs(PolygonArea(polygon)) < kMinAreaM2) {
    return absl::InvalidArgumentError(
        absl::StrCat(where, ": encloses no area (degenerate: collinear or repeated vertices)"));
  }
  // Neighbouring edges that fold back onto each other overlap along a stretch.
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& prev = polygon[(i + n - 1) % n];
    const Eigen::Vector2d& at = polygon[i];
    const Eigen::Vector2d& next = polygon[(i + 1) % n];
    if (std::abs(Cross(at, prev, next)) < 1e-12 && (prev - at).dot(next - at) > 0.0) {
      return absl::InvalidArgumentError(
          absl::StrCat(where, ": the edges at vertex ", i, " fold back (self-intersecting)"));
    }
  }
  return absl::OkStatus();
}

bool PolygonContains(const Polygon2& polygon, const Eigen::Vector2d& point) {
  bool inside = false;
  const size_t n = polygon.size();
  for (size_t i = 0, j = n - 1; i < n; j = i++) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[j];
    if (PointSegmentDistance(point, a, b) < 1e-12) return true;
    if ((a.y() > point.y()) != (b.y() > point.y()) &&
        point.x() < (b.x() - a.x()) * (point.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      inside = !inside;
    }
  }
  return inside;
}

double DistanceToPolygonBoundary(const Polygon2& polygon, const Eigen::Vector2d& point) {
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < polygon.size(); ++i) {
    best =
        std::min(best, PointSegmentDistance(point, polygon[i], polygon[(i + 1) % polygon.size()]));
  }
  return best;
}

bool DiscTouchesPolygon(const Polygon2& polygon, const Eigen::Vector2d& center, double radius_m) {
  return PolygonContains(polygon, center) ||
         DistanceToPolygonBoundary(polygon, center) <= std::max(radius_m, 0.0);
}

bool SegmentTouchesPolygon(const Polygon2& polygon, const Eigen::Vector2d& a,
                           const Eigen::Vector2d& b, double radius_m) {
  if (PolygonContains(polygon, a) || PolygonContains(polygon, b)) return true;
  for (size_t i = 0; i < polygon.size(); ++i) {
    if (SegmentSegmentDistance(a, b, polygon[i], polygon[(i + 1) % polygon.size()]) <=
        std::max(radius_m, 0.0)) {
      return true;
    }
  }
  return false;
}

absl::Status ZoneSet::Validate() const {
  std::set<std::string> names;
  for (size_t i = 0; i < zones.size(); ++i) {
    const Zone& zone = zones[i];
    const std::string where = absl::StrCat("zones[", i, "]");
    if (!IsValidZoneName(zone.name)) {
      return absl::InvalidArgumentError(
          absl::StrCat(where, ".name: must be 1-64 characters of [A-Za-z0-9_.-], got '",
                       EchoInput(zone.name), "'"));
    }
    if (!names.insert(zone.name).second) {
      return absl::InvalidArgumentError(
          absl::StrCat(where, ".name: zone '", zone.name, "' is named twice"));
    }
    RETURN_IF_ERROR(ValidatePolygon(zone.polygon_in_map, absl::StrCat(where, ".polygon")));
    if (zone.kind == ZoneKind::kSpeedLimit &&
        !(std::isfinite(zone.speed_limit_mps) && zone.speed_limit_mps > 0.0)) {
      return absl::InvalidArgumentError(absl::StrCat(
          where, ".speed_limit: must be a finite speed > 0 m/s, got ", zone.speed_limit_mps));
    }
    if (zone.kind == ZoneKind::kOneAtATime && zone.capacity < 1) {
      return absl::InvalidArgumentError(
          absl::StrCat(where, ".capacity: must be at least 1 robot, got ", zone.capacity));
    }
  }
  return absl::OkStatus();
}

const Zone* ZoneSet::Find(std::string_view name) const {
  for (const Zone& zone : zones) {
    if (zone.name == name) return &zone;
  }
  return nullptr;
}

bool ZoneSet::HasKind(ZoneKind kind) const {
  return std::any_of(zones.begin(), zones.end(),
                     [kind](const Zone& zone) { return zone.kind == kind; });
}

std::vector<const Zone*> ZoneSet::Touching(ZoneKind kind, const Eigen::Vector2d& point_in_map,
                                           double radius_m) const {
  std::vector<const Zone*> out;
  for (const Zone& zone : zones) {
    if (zone.kind == kind && DiscTouchesPolygon(zone.polygon_in_map, point_in_map, radius_m)) {
      out.push_back(&zone);
    }
  }
  return out;
}

std::optional<double> ZoneSet::SpeedLimitAt(const Eigen::Vector2d& point_in_map,
                                            double radius_m) const {
  std::optional<double> limit;
  for (const Zone* zone : Touching(ZoneKind::kSpeedLimit, point_in_map, radius_m)) {
    limit = std::min(limit.value_or(zone->speed_limit_mps), zone->speed_limit_mps);
  }
  return limit;
}

const OccupancyGrid& PlanningGrid(const OccupancyGrid& grid, const ZoneSet* zones,
                                  std::optional<OccupancyGrid>& storage) {
  if (zones == nullptr || !zones->HasKind(ZoneKind::kNoGo)) return grid;
  storage = WithNoGoZonesOccupied(grid, *zones);
  return *storage;
}

OccupancyGrid WithNoGoZonesOccupied(const OccupancyGrid& grid, const ZoneSet& zones) {
  OccupancyGrid out = grid;
  const double resolution_m = grid.resolution_m();
  const double cell_reach_m = 0.5 * std::sqrt(2.0) * resolution_m;
  const Eigen::Rotation2Dd to_grid(-grid.origin().yaw_rad());
  for (const Zone& zone : zones.zones) {
    if (zone.kind != ZoneKind::kNoGo) continue;
    // The zone's bounds in cells, then every cell in them that the zone overlaps.
    Eigen::Vector2d low = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector2d high = -low;
    for (const Eigen::Vector2d& vertex : zone.polygon_in_map) {
      const Eigen::Vector2d in_cells =
          to_grid * (vertex - grid.origin().translation()) / resolution_m;
      low = low.cwiseMin(in_cells);
      high = high.cwiseMax(in_cells);
    }
    const int x0 = std::max(0, static_cast<int>(std::floor(low.x())) - 1);
    const int y0 = std::max(0, static_cast<int>(std::floor(low.y())) - 1);
    const int x1 = std::min(grid.width() - 1, static_cast<int>(std::ceil(high.x())) + 1);
    const int y1 = std::min(grid.height() - 1, static_cast<int>(std::ceil(high.y())) + 1);
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const CellIndex cell{x, y};
        if (DiscTouchesPolygon(zone.polygon_in_map, grid.CellToWorld(cell), cell_reach_m)) {
          out.SetValue(cell, 100);
        }
      }
    }
  }
  return out;
}

absl::Status CheckZonesOnMap(const ZoneSet& zones, const OccupancyGrid& grid) {
  for (size_t i = 0; i < zones.zones.size(); ++i) {
    const Polygon2& polygon = zones.zones[i].polygon_in_map;
    for (size_t j = 0; j < polygon.size(); ++j) {
      if (!grid.ContainsWorld(polygon[j])) {
        return absl::InvalidArgumentError(
            absl::StrCat("zones[", i, "].polygon[", j, "]: (", polygon[j].x(), ", ", polygon[j].y(),
                         ") is off the map (zone '", zones.zones[i].name, "')"));
      }
    }
  }
  return absl::OkStatus();
}

}  // namespace fleetnav
