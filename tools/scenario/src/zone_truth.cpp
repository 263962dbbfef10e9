#include "fleetnav/scenario/zone_truth.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "absl/strings/str_format.h"

namespace fleetnav::scenario {
namespace {

// The footprint at a true pose, in the map frame.
Polygon2 Placed(const Polygon2& footprint, const TruthSample& sample) {
  const Eigen::Rotation2Dd rotation(sample.yaw_rad);
  const Eigen::Vector2d at(sample.x_m, sample.y_m);
  Polygon2 out;
  out.reserve(footprint.size());
  for (const Eigen::Vector2d& vertex : footprint) out.push_back(at + rotation * vertex);
  return out;
}

bool Overlaps(const Polygon2& zone, const Polygon2& body, const Eigen::Vector2d& center) {
  if (body.size() < 3) return PolygonContains(zone, center);
  for (size_t i = 0; i < body.size(); ++i) {
    if (SegmentTouchesPolygon(zone, body[i], body[(i + 1) % body.size()], 0.0)) return true;
  }
  // A zone wholly under the robot.
  return PolygonContains(body, zone.front());
}

const Polygon2& FootprintOf(const std::map<std::string, Polygon2>& footprints,
                            const std::string& robot_id) {
  static const Polygon2 kPoint;
  const auto it = footprints.find(robot_id);
  return it != footprints.end() ? it->second : kPoint;
}

}  // namespace

StopTruth JudgeStops(const std::vector<StopWindow>& stops,
                     const std::map<std::string, std::vector<TruthSample>>& truth,
                     const std::map<std::string, Polygon2>& footprints, double grace_s) {
  StopTruth out;
  for (const StopWindow& stop : stops) {
    const double from_s = stop.start_s + grace_s;
    for (const auto& [robot_id, samples] : truth) {
      const Polygon2& shape = FootprintOf(footprints, robot_id);
      const auto overlaps = [&](const TruthSample& s) {
        return Overlaps(stop.polygon, Placed(shape, s), Eigen::Vector2d(s.x_m, s.y_m));
      };
      const TruthSample* anchor = nullptr;
      bool applies = false;
      bool inside_before = false;
      for (const TruthSample& s : samples) {
        if (s.t_s < from_s || s.t_s > stop.end_s) continue;
        if (anchor == nullptr) {
          anchor = &s;
          applies = stop.polygon.empty() || overlaps(s);
          inside_before = applies;
          continue;
        }
        if (applies) {
          const double moved_m = std::hypot(s.x_m - anchor->x_m, s.y_m - anchor->y_m);
          if (moved_m > out.max_motion_while_stopped_m) {
            out.max_motion_while_stopped_m = moved_m;
            out.worst = absl::StrFormat(
                "%s moved %.3f m by %.2f s during the stop of %s", robot_id, moved_m, s.t_s,
                stop.zone.empty() ? "the whole fleet" : "zone '" + stop.zone + "'");
          }
        } else {
          const bool inside = overlaps(s);
          if (inside && !inside_before) ++out.stopped_zone_entries;
          inside_before = inside;
        }
      }
    }
  }
  return out;
}

namespace {

// Counts the robots in a one-at-a-time zone over time: the most at once, and the entries made
// when it was full.
void JudgeCapacity(const Zone& zone, const std::map<std::string, std::vector<TruthSample>>& truth,
                   const std::map<std::string, Polygon2>& footprints, ZoneTruth& out) {
  struct Change {
    double t_s = 0.0;
    bool enters = false;
    const std::string* robot_id = nullptr;
  };
  std::vector<Change> changes;
  for (const auto& [robot_id, samples] : truth) {
    const Polygon2& shape = FootprintOf(footprints, robot_id);
    bool inside_before = false;
    for (const TruthSample& s : samples) {
      const bool inside =
          Overlaps(zone.polygon_in_map, Placed(shape, s), Eigen::Vector2d(s.x_m, s.y_m));
      if (inside != inside_before) changes.push_back({s.t_s, inside, &robot_id});
      inside_before = inside;
    }
  }
  // At one time, leaving before entering.
  std::stable_sort(changes.begin(), changes.end(), [](const Change& a, const Change& b) {
    return a.t_s != b.t_s ? a.t_s < b.t_s : (!a.enters && b.enters);
  });
  int inside = 0;
  int& most = out.max_robots_in_zone[zone.name];
  for (const Change& change : changes) {
    if (!change.enters) {
      --inside;
      continue;
    }
    if (inside >= zone.capacity) {
      if (out.over_capacity_entries++ == 0) {
        out.first_over_capacity = absl::StrFormat(
            "%s entered one-at-a-time zone '%s' (admits %d) at %.2f s with %d inside",
            *change.robot_id, zone.name, zone.capacity, change.t_s, inside);
      }
    }
    most = std::max(most, ++inside);
  }
}

}  // namespace

ZoneTruth JudgeZones(const ZoneSet& zones,
                     const std::map<std::string, std::vector<TruthSample>>& truth,
                     const std::map<std::string, Polygon2>& footprints) {
  ZoneTruth out;
  for (const Zone& zone : zones.zones) {
    if (zone.kind == ZoneKind::kOneAtATime) JudgeCapacity(zone, truth, footprints, out);
  }
  double first_entry_s = 0.0;
  for (const auto& [robot_id, samples] : truth) {
    const Polygon2& shape = FootprintOf(footprints, robot_id);
    for (const Zone& zone : zones.zones) {
      bool inside_before = false;
      for (size_t i = 0; i < samples.size(); ++i) {
        const TruthSample& s = samples[i];
        const Eigen::Vector2d center(s.x_m, s.y_m);
        if (zone.kind == ZoneKind::kNoGo) {
          const bool inside = Overlaps(zone.polygon_in_map, Placed(shape, s), center);
          if (inside && !inside_before) {
            ++out.no_go_entries;
            if (out.first_no_go_entry.empty() || s.t_s < first_entry_s) {
              first_entry_s = s.t_s;
              out.first_no_go_entry = absl::StrFormat("%s entered no-go zone '%s' at %.2f s",
                                                      robot_id, zone.name, s.t_s);
            }
          }
          inside_before = inside;
        }
        if (i == 0) continue;
        const TruthSample& p = samples[i - 1];
        const double dt_s = s.t_s - p.t_s;
        if (dt_s <= 0.0 || !PolygonContains(zone.polygon_in_map, center) ||
            !PolygonContains(zone.polygon_in_map, Eigen::Vector2d(p.x_m, p.y_m))) {
          continue;
        }
        const double speed_mps = std::hypot(s.x_m - p.x_m, s.y_m - p.y_m) / dt_s;
        double& most = out.max_speed_in_zone_mps[zone.name];
        most = std::max(most, speed_mps);
      }
    }
  }
  return out;
}

ZoneTruth JudgeZonesOverTime(const std::vector<TimedZoneSet>& versions,
                             const std::map<std::string, std::vector<TruthSample>>& truth,
                             const std::map<std::string, Polygon2>& footprints) {
  ZoneTruth out;
  for (size_t v = 0; v < versions.size(); ++v) {
    const double from_s = versions[v].from_s;
    const double to_s =
        v + 1 < versions.size() ? versions[v + 1].from_s : std::numeric_limits<double>::infinity();
    std::map<std::string, std::vector<TruthSample>> window;
    for (const auto& [robot_id, samples] : truth) {
      for (const TruthSample& s : samples) {
        if (s.t_s >= from_s && s.t_s < to_s) window[robot_id].push_back(s);
      }
    }
    const ZoneTruth part = JudgeZones(versions[v].zones, window, footprints);
    out.no_go_entries += part.no_go_entries;
    if (out.first_no_go_entry.empty()) out.first_no_go_entry = part.first_no_go_entry;
    out.over_capacity_entries += part.over_capacity_entries;
    if (out.first_over_capacity.empty()) out.first_over_capacity = part.first_over_capacity;
    for (const auto& [zone, speed_mps] : part.max_speed_in_zone_mps) {
      double& most = out.max_speed_in_zone_mps[zone];
      most = std::max(most, speed_mps);
    }
    for (const auto& [zone, robots] : part.max_robots_in_zone) {
      int& most = out.max_robots_in_zone[zone];
      most = std::max(most, robots);
    }
  }
  return out;
}

}  // namespace fleetnav::scenario
