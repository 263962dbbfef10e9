#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "fleetnav/core/zone.hpp"
#include "fleetnav/planner/coordination/traffic_schedule.hpp"
#include "fleetnav/planner/grid/swept_cells.hpp"

namespace fleetnav::planner {

/// One-at-a-time zones (docs/server.md, "Zones") as traffic coordination keeps them: a zone
/// that admits `capacity` robots has `capacity` lanes, each route that enters the zone is given
/// one lane, and every action of the route whose region meets the zone (swept, where it stands
/// before or after) takes that lane's cells as well. A zone for one robot has one lane, its own
/// cells (every robot in it holds the whole zone); a zone for more has a token per lane, a cell
/// far off every map that no floor meets. Two routes in one lane then share floor in every
/// action they have in the zone, so the action dependency graph (DecideClearances) lets the
/// second in only after the first has finished its last action there, and holds it at the end
/// of its last action outside: at most `capacity` robots are in the zone at once, the queue
/// forms outside it, and the orders stay the graph's (acyclic, no new deadlock). A robot
/// standing without a job in a zone holds one lane until it is sent aside. Lanes are given
/// once per route and zone, the least used first, so a robot can wait for its lane while
/// another lane is free (the price of keeping the graph's orders). Value type.
class CapacityZones {
 public:
  CapacityZones() = default;
  /// The one-at-a-time zones of `zones`, on cells of side `cell_m` (as the routes' regions).
  static CapacityZones Of(const ZoneSet& zones, double cell_m);

  bool empty() const { return zones_.empty(); }
  size_t size() const { return zones_.size(); }
  const std::string& name(size_t zone) const { return zones_[zone].name; }
  int capacity(size_t zone) const { return static_cast<int>(zones_[zone].lanes.size()); }
  /// Indices of the zones whose cells `cells` meets.
  std::vector<size_t> Meeting(const CellSet& cells) const;
  /// Whether `cells` meets zone `zone`.
  bool Meets(size_t zone, const CellSet& cells) const {
    return cells.Intersects(zones_[zone].cells);
  }

  /// Adds to each region of `route` (start, every action's swept and end cells) that meets a
  /// zone the cells of the route's lane of that zone. `lanes` holds the route's lane per zone
  /// name; a zone it has none for yet is given `choose(zone index)` (0 <= lane < capacity),
  /// kept there so that the route keeps its lane when it is predicted again.
  void Apply(ScheduledRoute& route, std::map<std::string, int>& lanes,
             const std::function<int(size_t)>& choose) const;
  /// Where a robot stands (`cells`) with the cells of lane `lane_of(zone index)` of each zone
  /// it meets added.
  CellSet Standing(const CellSet& cells, const std::function<int(size_t)>& lane_of) const;

 private:
  struct Entry {
    std::string name;
    CellSet cells;
    std::vector<CellSet> lanes;
  };
  /// Adds to `cells` the lanes of the zones it meets; new lanes chosen into `lanes`.
  void AddLanes(CellSet& cells, std::map<std::string, int>& lanes,
                const std::function<int(size_t)>& choose) const;

  std::vector<Entry> zones_;
};

/// Cells from here on (in x and y) are lane tokens, not floor: 2^29 cells is beyond 10^7 km at
/// any cell size used.
inline constexpr int64_t kLaneTokenCell = int64_t{1} << 29;

/// The lane of a zone least used by `lanes_in_use` (the lanes other routes hold in it; lanes
/// out of range are ignored), the lowest of those tied.
int LeastUsedLane(int capacity, const std::vector<int>& lanes_in_use);

}  // namespace fleetnav::planner
