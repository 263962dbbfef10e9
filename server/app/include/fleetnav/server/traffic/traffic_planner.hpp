#pragma once

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/traffic_plan.hpp"
#include "fleetnav/server/site/site_cache.hpp"
#include "fleetnav/server/site/zone_catalog.hpp"

namespace fleetnav::server {

/// Coordinated paths for several robots on one map (PlanPaths). Up to 12 robots of which some
/// drive differentially (the Lely must not reverse) are first planned with headings
/// and footprints (planner::PlanKinematicTraffic: cells as wide as the smallest robot, each
/// robot covering the cells its circumscribed disc touches, the Lely never reversing) with half
/// the budget. Otherwise, or when that does not fit or finish, the map is coarsened to a
/// 4-connected grid whose cells are as wide as the largest robot (a coarse cell is free only if
/// every map cell in it is free), starts and goals are snapped to their cells, and the
/// multi-robot planner (EECBS for tens, LaCAM for hundreds, refined by LNS; rotations removed;
/// planner/) solves it as point robots within the rest of the time. Either plan is compiled into
/// an action dependency graph (Hönig et al., RA-L 2019) so that it stays collision-free under
/// any delay. Robots are planned on the map with the no-go zones of its latest zone set occupied
/// (WithNoGoZonesOccupied), as the agents plan. Thread-safe as its repository is.
class TrafficPlanner {
 public:
  explicit TrafficPlanner(SiteCache* site_data) : site_data_(site_data) {}
  /// The zones whose no-go areas the plans keep out of. Set before the planner is shared;
  /// without it plans use the map alone.
  void UseZones(ZoneCatalog* zones) { zones_ = zones; }

  /// InvalidArgument names `agents[i]` for an unknown kind, a start or goal off the free grid,
  /// or two robots on one cell; NotFound for the map; DeadlineExceeded when no plan is found
  /// in time.
  absl::StatusOr<TrafficPlan> Plan(const std::string& map_id, uint32_t map_version,
                                   const std::vector<TrafficAgent>& agents, double time_limit_s);

 private:
  SiteCache* site_data_;
  ZoneCatalog* zones_ = nullptr;
};

}  // namespace fleetnav::server
