#include "fleetnav/planner/coordination/capacity_zones.hpp"

#include <algorithm>

namespace fleetnav::planner {

CapacityZones CapacityZones::Of(const ZoneSet& zones, double cell_m) {
  CapacityZones out;
  for (const Zone& zone : zones.zones) {
    if (zone.kind != ZoneKind::kOneAtATime) continue;
    Entry entry;
    entry.name = zone.name;
    // The polygon placed at the map frame's origin: every cell it covers or touches.
    entry.cells = CellSet::Sweep({Pose2()}, zone.polygon_in_map, 0.0, cell_m);
    const int lanes = std::max(1, zone.capacity);
    if (lanes == 1) {
      entry.lanes.push_back(entry.cells);
    } else {
      const auto zone_index = static_cast<int64_t>(out.zones_.size());
      for (int lane = 0; lane < lanes; ++lane) {
        entry.lanes.push_back(CellSet::OfCell(kLaneTokenCell + zone_index, kLaneTokenCell + lane));
      }
    }
    out.zones_.push_back(std::move(entry));
  }
  return out;
}

std::vector<size_t> CapacityZones::Meeting(const CellSet& cells) const {
  std::vector<size_t> out;
  for (size_t z = 0; z < zones_.size(); ++z) {
    if (cells.Intersects(zones_[z].cells)) out.push_back(z);
  }
  return out;
}

void CapacityZones::AddLanes(CellSet& cells, std::map<std::string, int>& lanes,
                             const std::function<int(size_t)>& choose) const {
  for (const size_t z : Meeting(cells)) {
    auto [it, inserted] = lanes.try_emplace(zones_[z].name, 0);
    if (inserted) it->second = std::clamp(choose(z), 0, capacity(z) - 1);
    cells.Add(zones_[z].lanes[std::clamp(it->second, 0, capacity(z) - 1)]);
  }
}

void CapacityZones::Apply(ScheduledRoute& route, std::map<std::string, int>& lanes,
                          const std::function<int(size_t)>& choose) const {
  if (zones_.empty()) return;
  AddLanes(route.start_cells, lanes, choose);
  for (CellSet& cells : route.action_cells) AddLanes(cells, lanes, choose);
  for (CellSet& cells : route.action_end_cells) AddLanes(cells, lanes, choose);
}

CellSet CapacityZones::Standing(const CellSet& cells,
                                const std::function<int(size_t)>& lane_of) const {
  CellSet out = cells;
  for (const size_t z : Meeting(cells)) {
    out.Add(zones_[z].lanes[std::clamp(lane_of(z), 0, capacity(z) - 1)]);
  }
  return out;
}

int LeastUsedLane(int capacity, const std::vector<int>& lanes_in_use) {
  std::vector<int> count(std::max(1, capacity), 0);
  for (const int lane : lanes_in_use) {
    if (lane >= 0 && lane < static_cast<int>(count.size())) ++count[lane];
  }
  return static_cast<int>(std::min_element(count.begin(), count.end()) - count.begin());
}

}  // namespace fleetnav::planner
