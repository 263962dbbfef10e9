#include "fleetnav/server/site/goal_reachability.hpp"

#include <cmath>
#include <utility>

#include "absl/strings/str_format.h"
#include "fleetnav/planner/grid/costmap.hpp"
#include "fleetnav/planner/grid/free_space_regions.hpp"

namespace fleetnav::server {
namespace {

/// A robot standing nearer an obstacle than its inscribed circle (beside a wall, under a
/// trolley) is taken to be in the region of the nearest free space this close.
constexpr double kStandingNearM = 0.3;

}  // namespace

struct GoalReachability::Entry {
  planner::Costmap costmap;
  planner::FreeSpaceRegions regions;
  Pose2 grid_from_map;
};

GoalReachability::GoalReachability(SiteCache* site_data) : site_data_(site_data) {}

GoalReachability::~GoalReachability() = default;

absl::Status GoalReachability::Check(const std::string& map_id, uint32_t map_version,
                                     const RobotModel& model, const Eigen::Vector2d& goal_in_map,
                                     const std::optional<Pose2>& from_in_map,
                                     const std::string& who) {
  absl::MutexLock lock(&mutex_);
  const auto key = std::make_tuple(map_id, map_version, model.kind_name);
  auto it = entries_.find(key);
  if (it == entries_.end()) {
    absl::StatusOr<std::shared_ptr<const storage::StoredMap>> map =
        site_data_->Map(map_id, map_version);
    if (!map.ok()) return map.status();
    absl::StatusOr<planner::Costmap> costmap =
        planner::Costmap::Build((*map)->grid, model.footprint_m, planner::CostmapParams{});
    if (!costmap.ok()) return costmap.status();
    planner::FreeSpaceRegions regions(*costmap);
    if (entries_.size() >= kMaxEntries) entries_.clear();
    it = entries_
             .emplace(key, std::make_unique<Entry>(Entry{*std::move(costmap), std::move(regions),
                                                         (*map)->grid.origin().Inverse()}))
             .first;
  }
  Entry& entry = *it->second;
  const Eigen::Vector2d goal = entry.grid_from_map.TransformPoint(goal_in_map);
  const double res_m = entry.costmap.resolution_m();
  const int gx = static_cast<int>(std::floor(goal.x() / res_m));
  const int gy = static_cast<int>(std::floor(goal.y() / res_m));
  if (!entry.costmap.InBounds(gx, gy) || !entry.costmap.AnyYawFree(gx, gy)) {
    return absl::FailedPreconditionError(absl::StrFormat(
        "%s does not fit at (%.2f, %.2f) at any heading: its footprint overlaps an obstacle of "
        "map '%s' there",
        who, goal_in_map.x(), goal_in_map.y(), map_id));
  }
  if (!from_in_map) return absl::OkStatus();
  const Eigen::Vector2d from = entry.grid_from_map.TransformPoint(from_in_map->translation());
  const int from_region = entry.regions.RegionNear(from, kStandingNearM);
  // Not on this map's free space: it stands on another map, or it is lost; nothing is known.
  if (from_region == planner::FreeSpaceRegions::kNone) return absl::OkStatus();
  if (entry.regions.RegionNear(goal, 2.0 * res_m) != from_region) {
    return absl::FailedPreconditionError(absl::StrFormat(
        "%s cannot reach (%.2f, %.2f) from where it stands (%.2f, %.2f): no way on map '%s' "
        "between the two is as wide as its footprint's inscribed circle (%.2f m across)",
        who, goal_in_map.x(), goal_in_map.y(), from_in_map->x_m(), from_in_map->y_m(), map_id,
        2.0 * entry.costmap.inscribed_radius_m()));
  }
  return absl::OkStatus();
}

}  // namespace fleetnav::server
