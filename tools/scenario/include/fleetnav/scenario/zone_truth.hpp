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
};

/// Judges recorded true poses against `zones`, each robot with its footprint (a polygon in
/// base_link; robots without one count as a point). Pure function.
ZoneTruth JudgeZones(const ZoneSet& zones,
                     const std::map<std::string, std::vector<TruthSample>>& truth,
                     const std::map<std::string, Polygon2>& footprints);

}  // namespace fleetnav::scenario
