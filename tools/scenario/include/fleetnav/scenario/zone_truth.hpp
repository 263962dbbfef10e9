#pragma once

#include <map>
#include <string>
#include <vector>

#include "fleetnav/core/zone.hpp"
#include "fleetnav/scenario/standstill.hpp"

namespace fleetnav::scenario {

/// What the simulator's ground truth says of a run's zones (issue 39).
struct ZoneTruth {
  /// Episodes of a robot's true footprint overlapping a no-go zone: a run of samples in which
  /// it overlaps the same zone counts once.
  int no_go_entries = 0;
  /// The first of them, in words ("omni1 entered no-go zone 'pen' at 12.30 s"); empty: none.
  std::string first_no_go_entry;
  /// Per zone, the highest true speed (m/s, base_link) of a robot whose centre lay inside the
  /// zone at both ends of a sample step; zones no robot drove in are absent.
  std::map<std::string, double> max_speed_in_zone_mps;
  /// Per one-at-a-time zone, the most robots whose true footprints overlapped it at once.
  std::map<std::string, int> max_robots_in_zone;
  /// Entries of a robot into a one-at-a-time zone that already held as many robots as it
  /// admits (a robot that leaves at the sample time another enters has left first).
  int over_capacity_entries = 0;
  std::string first_over_capacity;  ///< the first of them, in words; empty: none
};

/// An operator's stop during a run: from `start_s` to `end_s` (sim time), of the whole fleet
/// (`polygon` empty) or of a zone.
struct StopWindow {
  double start_s = 0.0;
  double end_s = 0.0;
  std::string zone;  ///< "" for the whole fleet
  Polygon2 polygon;
};

/// What the truth says of the robots during operators' stops, from `grace_s` after each stop
/// was made (the command's way to the robot and its braking) to its end.
struct StopTruth {
  /// The farthest a robot the stop applied to (the whole fleet, or its footprint overlapping
  /// the zone when the grace ended) moved from where it stood then.
  double max_motion_while_stopped_m = 0.0;
  std::string worst;  ///< that robot and stop, in words; empty when none moved
  /// Entries of robots that were outside a stopped zone into it while it was stopped.
  int stopped_zone_entries = 0;
};

/// Judges recorded true poses against the stops made in a run. Pure function.
StopTruth JudgeStops(const std::vector<StopWindow>& stops,
                     const std::map<std::string, std::vector<TruthSample>>& truth,
                     const std::map<std::string, Polygon2>& footprints, double grace_s = 2.0);

/// Judges recorded true poses against `zones`, each robot with its footprint (a polygon in
/// base_link; robots without one count as a point). Pure function.
ZoneTruth JudgeZones(const ZoneSet& zones,
                     const std::map<std::string, std::vector<TruthSample>>& truth,
                     const std::map<std::string, Polygon2>& footprints);

/// A version of a map's zones and the sim time from which it was in force.
struct TimedZoneSet {
  double from_s = 0.0;
  ZoneSet zones;
};

/// JudgeZones for zones that changed during the run: each version (in time order) judges the
/// samples from its time until the next version's, and the figures add up (entries) or take
/// the highest (speeds, robots at once). A robot a new no-go zone is put on counts as entering
/// it. Pure function.
ZoneTruth JudgeZonesOverTime(const std::vector<TimedZoneSet>& versions,
                             const std::map<std::string, std::vector<TruthSample>>& truth,
                             const std::map<std::string, Polygon2>& footprints);

}  // namespace fleetnav::scenario
