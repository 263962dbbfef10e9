#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <random>
#include <stop_token>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/planner/mapf/constraint_table.hpp"
#include "fleetnav/planner/mapf/mapf.hpp"
#include "fleetnav/planner/mapf/sipp.hpp"

namespace fleetnav::planner {

/// Parameters of LnsRefiner.
struct LnsParams {
  double time_limit_s = 1.0;  ///< wall-clock budget of one Refine or RemoveRotations, > 0
  uint64_t seed = 0;          ///< neighbourhood choice and replanning order
  int neighborhood_size = 8;  ///< agents replanned per iteration, ≥ 2
  /// Replanned agents never enter a vertex another robot held the step before, so no rotation
  /// (robots following each other around a cycle in one step) can include them.
  bool forbid_following = false;

  absl::Status Validate() const;
};

/// What one LnsRefiner run did.
struct LnsStats {
  int64_t iterations = 0;
  int64_t accepted = 0;
  int64_t initial_soc = 0;
  int64_t final_soc = 0;
  double last_improvement_ms = 0.0;  ///< since the start of Refine
};

/// Anytime improvement of a valid multi-robot plan by large neighbourhood search (Li, Chen,
/// Harabor, Stuckey and Koenig, "Anytime Multi-Agent Path Finding via Large Neighborhood
/// Search", IJCAI 2021): each iteration removes the paths of a few agents, replans them one by
/// one in random order with SIPP against everyone else's paths (prioritized planning), and keeps
/// the result only if the sum of costs drops. Neighbourhoods come from three heuristics chosen
/// by adaptive weights: agent-based (the agent with the largest delay plus the agents in the way
/// of its shortest path), intersection-based (agents passing one junction) and random. Each
/// agent may keep a committed prefix of its path (its first `fixed_steps[i]` entries), which
/// replanning never changes — the way a plan is repaired from the robots' current positions.
/// The same machinery removes rotations: RemoveRotations replans the robots of each rotation,
/// alternately with following forbidden and freely (kept only if rotations became fewer),
/// until none is left. Holds a reference to the instance's graph.
/// One call at a time per object.
class LnsRefiner {
 public:
  LnsRefiner(const MapfInstance& instance, const LnsParams& params);
  ~LnsRefiner();

  /// Called with each improved plan and the milliseconds since Refine began.
  using ImprovementObserver = std::function<void(const MapfSolution&, double elapsed_ms)>;

  /// Improves `initial` (which must pass ValidateSolution) until the budget or `stop` ends;
  /// `fixed_steps` is empty (every agent keeps only its start) or one entry ≥ 1 per agent.
  /// Errors: InvalidArgument (bad params, plan or fixed_steps).
  absl::StatusOr<MapfSolution> Refine(const MapfSolution& initial, std::stop_token stop = {},
                                      std::vector<int> fixed_steps = {}, LnsStats* stats = nullptr,
                                      const ImprovementObserver& on_improved = nullptr);

  /// A plan without rotations, from `initial` by replanning the robots of each rotation.
  /// Errors: InvalidArgument (bad plan), DeadlineExceeded (rotations left when the budget
  /// ended), Cancelled.
  absl::StatusOr<MapfSolution> RemoveRotations(const MapfSolution& initial,
                                               std::stop_token stop = {},
                                               std::vector<int> fixed_steps = {});

 private:
  absl::Status Load(const MapfSolution& initial, std::vector<int> fixed_steps);
  // Replans `agents` in the given order against the table; on failure restores the old paths
  // and returns false. On success the new paths are in paths_ and the table.
  bool Replan(const std::vector<int>& agents, bool no_following,
              std::vector<std::vector<int>>* old_paths);
  void Restore(const std::vector<int>& agents, std::vector<std::vector<int>>& old_paths);
  std::vector<int> Tail(int agent) const;
  void AddToTable(int agent);
  void RemoveFromTable(int agent);
  DistanceTable& Distances(int agent);
  int64_t Cost(int agent) const;
  std::vector<int> AgentBasedNeighborhood();
  std::vector<int> IntersectionNeighborhood();
  std::vector<int> RandomNeighborhood();
  void IndexVisitors(int agent, bool add);

  MapfInstance instance_;
  LnsParams params_;
  std::mt19937_64 rng_;
  ConstraintTable table_;
  SippPlanner sipp_;
  std::vector<std::unique_ptr<DistanceTable>> distances_;
  std::vector<std::vector<int>> paths_;
  std::vector<int> fixed_steps_;
  std::vector<std::vector<int>> visitors_;  // per vertex: agents whose path visits it
  std::vector<int> mark_;                   // per agent: stamp for de-duplication
  int mark_stamp_ = 0;
  std::vector<bool> tabu_;
  std::vector<int64_t> shortest_;  // per agent: the cost of its shortest path after its prefix  //
                                   // per agent: chosen by the agent-based heuristic this round
  // Replan gives up on an iteration once this passes (Refine sets it; RemoveRotations keeps it
  // at the far future, since a plan with a rotation is no use).
  std::chrono::steady_clock::time_point deadline_ = std::chrono::steady_clock::time_point::max();
};

/// Number of rotations in `solution` (each cycle at each step counted once).
int CountRotations(const MapfSolution& solution);

/// Agents of the first rotation in `solution` (robots that each move, in the same step, into
/// the vertex the next one leaves, closing a cycle), with the step in *step; empty if none.
std::vector<int> FindRotation(const MapfSolution& solution, int* step);

}  // namespace fleetnav::planner
