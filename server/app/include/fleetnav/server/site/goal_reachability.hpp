#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>

#include "absl/status/status.h"
#include "absl/synchronization/mutex.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/server/site/site_cache.hpp"

namespace fleetnav::planner {
class Costmap;
class FreeSpaceRegions;
}  // namespace fleetnav::planner

namespace fleetnav::server {

/// Whether a robot of a kind can stand at a goal on a stored map, and drive there from where it
/// stands: its footprint (unpadded) must be free of the map's obstacles at some heading at the
/// goal, and the goal must lie in the same planner::FreeSpaceRegions region as the robot, so a
/// goal in a gap narrower than the robot or in a closed room is refused at submission instead
/// of sending a robot that searches and fails. Both tests are necessary conditions only (a goal
/// that passes may still be unreachable in ways only a search finds), so nothing a robot can
/// reach is refused. The costmap and regions of each (map, version, kind) are built on first
/// use and kept. Thread-safe (one mutex).
class GoalReachability {
 public:
  explicit GoalReachability(SiteCache* site_data);
  ~GoalReachability();
  GoalReachability(const GoalReachability&) = delete;
  GoalReachability& operator=(const GoalReachability&) = delete;

  /// OK when `model` fits at `goal_in_map` and, when `from_in_map` is given and lies on the
  /// map's free space, the goal is in its region. Otherwise FailedPrecondition saying which
  /// test failed, with `who` (e.g. "robot omni3 (mecanum)") as the subject; errors reading the
  /// map are returned as they are.
  absl::Status Check(const std::string& map_id, uint32_t map_version, const RobotModel& model,
                     const Eigen::Vector2d& goal_in_map, const std::optional<Pose2>& from_in_map,
                     const std::string& who);

 private:
  struct Entry;
  /// At most this many (map, version, kind) entries are kept; all are dropped beyond it.
  static constexpr size_t kMaxEntries = 16;

  SiteCache* site_data_;
  absl::Mutex mutex_;
  std::map<std::tuple<std::string, uint32_t, std::string>, std::unique_ptr<Entry>> entries_
      ABSL_GUARDED_BY(mutex_);
};

}  // namespace fleetnav::server
