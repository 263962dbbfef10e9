// One-at-a-time zones in traffic coordination (docs/server.md, "Zones"): the lanes of
// planner::CapacityZones added to the schedules and to the robots that stand in the zones.
#include <algorithm>
#include <vector>

#include "fleetnav/server/traffic/traffic_coordinator.hpp"

namespace fleetnav::server {

std::shared_ptr<const planner::CapacityZones> TrafficCoordinator::CapacityZonesOf(
    const std::string& map_id) {
  if (zones_ == nullptr) return nullptr;
  const std::shared_ptr<const storage::StoredZoneSet> latest = zones_->Latest(map_id);
  if (latest == nullptr || !latest->zones.HasKind(ZoneKind::kOneAtATime)) {
    capacity_zones_.erase(map_id);
    return nullptr;
  }
  BuiltCapacityZones& built = capacity_zones_[map_id];
  if (built.zones == nullptr || built.version != latest->version) {
    built.version = latest->version;
    built.zones = std::make_shared<const planner::CapacityZones>(
        planner::CapacityZones::Of(latest->zones, params_.cell_m));
  }
  return built.zones;
}

void TrafficCoordinator::KeepCapacityZones(Tracked& tracked) {
  const std::string& map_id = tracked.assignment.job.map_id;
  const std::shared_ptr<const planner::CapacityZones> zones = CapacityZonesOf(map_id);
  if (zones == nullptr || !tracked.schedule) return;
  zones->Apply(*tracked.schedule, tracked.zone_lanes, [&](size_t zone) {
    // The lanes of the other jobs of the map that still have to drive through the zone.
    std::vector<int> in_use;
    for (const auto& [job_id, other] : jobs_) {
      if (&other == &tracked || other.assignment.job.map_id != map_id || !other.schedule) continue;
      const auto lane = other.zone_lanes.find(zones->name(zone));
      if (lane == other.zone_lanes.end()) continue;
      const planner::ScheduledRoute& route = *other.schedule;
      for (auto k = static_cast<size_t>(std::max(route.first_unfinished, 0));
           k < route.action_cells.size(); ++k) {
        if (zones->Meets(zone, route.action_cells[k])) {
          in_use.push_back(lane->second);
          break;
        }
      }
    }
    return planner::LeastUsedLane(zones->capacity(zone), in_use);
  });
}

const std::vector<planner::ParkedRobot>& TrafficCoordinator::ParkedWithCapacityZones(
    const std::string& map_id, const std::vector<planner::ParkedRobot>& parked,
    std::vector<planner::ParkedRobot>& storage) {
  const std::shared_ptr<const planner::CapacityZones> zones = CapacityZonesOf(map_id);
  if (zones == nullptr) return parked;
  storage.clear();
  storage.reserve(parked.size());
  for (const planner::ParkedRobot& robot : parked) {
    const auto last = last_zone_lanes_.find(robot.robot_id);
    storage.push_back({robot.robot_id, zones->Standing(robot.cells, [&](size_t zone) {
                         if (last == last_zone_lanes_.end()) return 0;
                         const auto lane = last->second.find(zones->name(zone));
                         return lane != last->second.end() ? lane->second : 0;
                       })});
  }
  return storage;
}

}  // namespace fleetnav::server
