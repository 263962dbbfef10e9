#pragma once

#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace fleetnav::planner {

/// A stretch of steps [begin_step, end_step) in which a vertex has no hard reservation
/// (end_step is ConstraintTable::kForever when it never ends). `conflicts` counts the soft
/// reservations inside it; a stretch holding a soft step is exactly one step long.
struct SafeInterval {
  int begin_step = 0;
  int end_step = 0;
  int conflicts = 0;
};

/// Space-time reservations on a graph for single-agent searches, in two channels: hard ones
/// the search must respect (CBS constraints, the paths of robots planned earlier) and soft ones
/// it should avoid (the current paths of the other agents, counted as conflicts). A path
/// reserves its vertex at every step from `start_step`, its last vertex for ever after
/// ("parked"), and each of its moves blocks the opposite move at the same step (a swap). From
/// these the table derives, per vertex, the safe intervals of Safe Interval Path Planning
/// (Phillips and Likhachev, ICRA 2011), cut wherever the soft occupancy changes as in SIPPS (Li
/// et al., "MAPF-LNS2: Fast Repairing for Multi-Agent Path Finding via Large Neighborhood
/// Search", AAAI 2022). Paths can be added and removed again; intervals are cached per vertex
/// until that vertex changes. Storage is per touched vertex, so clearing costs what was added.
/// Not thread-safe.
class ConstraintTable {
 public:
  static constexpr int kForever = std::numeric_limits<int>::max();

  explicit ConstraintTable(int num_vertices);

  /// Removes every reservation.
  void Clear();

  /// Forbids vertex v at `step`.
  void AddHardVertex(int v, int step);
  /// Forbids the move from → to that arrives at `step`.
  void AddHardEdge(int from, int to, int step);
  /// Reserves `path` (path[k] at step start_step + k) as hard; with `park` its last vertex
  /// stays reserved for ever.
  void AddHardPath(const std::vector<int>& path, int start_step = 0, bool park = true);
  /// Undoes AddHardPath with the same arguments.
  void RemoveHardPath(const std::vector<int>& path, int start_step = 0, bool park = true);
  /// Reserves `path` as soft (conflicts to avoid); same layout as AddHardPath.
  void AddSoftPath(const std::vector<int>& path, int start_step = 0, bool park = true);

  /// Whether the move from → to arriving at `step` is forbidden (a hard edge, or the swap of
  /// a hard path's move).
  bool HardEdgeBlocked(int from, int to, int step) const;
  /// How many soft paths swap with the move from → to arriving at `step`.
  int SoftEdgeConflicts(int from, int to, int step) const;
  /// The safe intervals of v in increasing order. Valid until the next change of the table.
  const std::vector<SafeInterval>& Intervals(int v);

 private:
  struct VertexRecord {
    std::vector<int> hard_steps;
    std::vector<int> hard_park_steps;
    std::vector<int> soft_steps;
    std::vector<int> soft_park_steps;
    std::vector<std::pair<int, int>> hard_in_moves;  // (from, step) of blocked moves into here
    std::vector<std::pair<int, int>> soft_in_moves;
    std::vector<SafeInterval> intervals;
    bool touched = false;
    bool intervals_valid = false;
  };
  VertexRecord& Touch(int v);
  void ChangePath(const std::vector<int>& path, int start_step, bool park, bool hard, int delta);
  static void BuildIntervals(VertexRecord& r);

  std::vector<VertexRecord> vertices_;
  std::vector<int> touched_;
};

}  // namespace fleetnav::planner
