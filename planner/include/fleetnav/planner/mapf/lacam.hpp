#pragma once

#include <cstdint>
#include <stop_token>
#include <vector>

#include "absl/container/flat_hash_set.h"
#include "absl/status/statusor.h"
#include "fleetnav/planner/mapf/mapf.hpp"
#include "fleetnav/planner/mapf/mapf_solver.hpp"

namespace fleetnav::planner {

/// Parameters of LacamSolver.
struct LacamParams {
  bool anytime = true;  ///< keep refining (LaCAM*) after the first plan until stopped
  uint64_t seed = 0;    ///< tie-breaking of PIBT candidates and successor order
  /// Memory cap: search nodes stop being created once this many agent positions are stored
  /// (about 12 bytes each). Refinement then ends; before a first plan it is ResourceExhausted.
  int64_t max_stored_agent_states = 40'000'000;

  absl::Status Validate() const;
};

/// Lazy Constraints Addition search for MAPF: LaCAM (Okumura, "LaCAM: Search-Based Algorithm
/// for Quick Multi-Agent Pathfinding", AAAI 2023) with the LaCAM* refinement (Okumura,
/// "Improving LaCAM for Scalable Eventually Optimal Multi-Agent Pathfinding", IJCAI 2023):
/// a depth-first search over whole configurations whose successors are generated one at a
/// time by PIBT (Okumura et al., "Priority Inheritance with Backtracking for Iterative
/// Multi-agent Path Finding", AIJ 2022) under lazily added low-level constraints; once the
/// goal configuration is found the search keeps running, rewiring parents by Dijkstra over the
/// explored graph, and returns the cheapest plan found (sum of loss) when the stop condition or
/// the memory cap ends it; each cheaper plan goes to the observer as it is found. Complete for
/// solvable instances given time; eventually optimal for sum of loss. Configurations, priorities
/// and orders live in flat arenas; the hot loop (PIBT) uses preallocated scratch arrays only. One
/// Solve at a time per object.
class LacamSolver : public MapfSolver {
 public:
  explicit LacamSolver(const LacamParams& params);

  std::string Name() const override { return "lacam"; }
  double SuboptimalityBound() const override { return 0.0; }
  /// NotFound when the search space is exhausted without reaching the goals.
  absl::StatusOr<MapfResult> Solve(const MapfInstance& instance, const MapfStopCondition& stop,
                                   const MapfPlanObserver& on_plan = nullptr) override;

 private:
  struct HighNode {
    int64_t offset;  // into config_/order_ (n entries) and priority_
    uint64_t hash;
    int parent;
    int64_t g;
    int64_t h;
    int low_head;
    int low_tail;
    int edge_head;
  };
  struct LowNode {
    int parent;
    int who;
    int where;
    int depth;
    int next;
  };
  struct Edge {
    int to;
    int64_t cost;
    int next;
  };
  struct NodeHash {
    const LacamSolver* s;
    size_t operator()(int id) const { return s->nodes_[id].hash; }
  };
  struct NodeEq {
    const LacamSolver* s;
    bool operator()(int a, int b) const;
  };

  int Dist(int agent, int v) { return tables_[agent].Get(v); }
  const int* Config(int node) const { return &config_[nodes_[node].offset]; }
  int PushLow(int node, int parent, int who, int where, int depth);
  // Creates a node from the configuration in next_; returns its id, or the id of the equal
  // node already stored (then *is_new is false).
  int InternNode(int parent, bool* is_new);
  bool Generate(int node, int low);
  bool Pibt(int agent, const int* from);
  void Shuffle(int* values, int count);
  // PIBT with swap (Okumura, IJCAI 2023, section 4.2): the robot i must swap places with, or
  // kNone. SwapRequired simulates the pusher driving the puller back along a corridor;
  // SwapPossible looks for a junction behind the puller where the two can pass.
  int SwapPartner(int i, const int* from, int target);
  bool SwapRequired(int pusher, int puller, int v_pusher, int v_puller);
  bool SwapPossible(int v_pusher_origin, int v_puller_origin) const;
  // Neighbours of v other than from_v that a robot could step into (a dead end where a robot
  // rests at its goal does not count); the last one in *next.
  int CorridorStep(int from_v, int v, int* next) const;
  // A dead end (degree 1) where a robot rests at its goal.
  bool RestingInDeadEnd(int u) const;
  int64_t EdgeCost(int a, int b) const;
  void AddEdge(int from, int to);
  void Rewire(int from);
  MapfSolution Backtrack(int node) const;

  MapfInstance instance_;
  LacamParams params_;
  int n_ = 0;
  std::vector<DistanceTable> tables_;
  uint64_t rng_state_ = 0;  // SplitMix64

  std::vector<HighNode> nodes_;
  std::vector<int> config_;
  std::vector<int> order_;
  std::vector<float> priority_;
  std::vector<LowNode> low_;
  std::vector<Edge> edges_;
  absl::flat_hash_set<int, NodeHash, NodeEq> explored_;

  // PIBT scratch, sized once.
  std::vector<int> next_;           // per agent: next vertex, or -1
  std::vector<int> occupied_now_;   // per vertex: agent, or -1
  std::vector<int> occupied_next_;  // per vertex: agent, or -1
  std::vector<int> candidates_;     // 5 per agent
  std::vector<int> sort_scratch_;
};

}  // namespace fleetnav::planner
