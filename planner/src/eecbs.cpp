#include "fleetnav/planner/eecbs.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <queue>
#include <set>
#include <tuple>

#include "absl/container/flat_hash_map.h"
#include "absl/container/flat_hash_set.h"
#include "absl/strings/str_cat.h"

namespace fleetnav::planner {
namespace {

constexpr int kNone = -1;

using Path = std::vector<int>;

int At(const Path& p, int t) { return t < static_cast<int>(p.size()) ? p[t] : p.back(); }

// A constraint forbids `agent` to be at vertex `to` at step t (from == kNone), or to move
// from `from` to `to` arriving at step t.
struct Constraint {
  int agent;
  int from;
  int to;
  int t;
};

struct Conflict {
  int a = kNone;
  int b = kNone;
  int u = kNone;  // a's vertex at t (vertex conflict) or a's origin (edge conflict)
  int v = kNone;  // kNone for a vertex conflict, else a's destination
  int t = 0;
};

// One constraint-tree node. Paths are shared between a node and its children; a child owns
// only the path it replanned.
struct CtNode {
  int parent;
  Constraint constraint;
  std::vector<std::shared_ptr<const Path>> paths;
  int64_t cost;
  int conflicts;
  Conflict first;
};

int64_t Key(int v, int t) { return (static_cast<int64_t>(t) << 32) | static_cast<uint32_t>(v); }
int64_t EdgeKey(int u, int v, int t) {
  return (static_cast<int64_t>(t) << 40) ^ (static_cast<int64_t>(u) << 20) ^ v;
}

// Counts the conflicting pairs of a set of paths and returns the earliest conflict.
int CountConflicts(const std::vector<std::shared_ptr<const Path>>& paths, int num_vertices,
                   std::vector<int>& owner, std::vector<int>& stamp, Conflict* first) {
  const int n = static_cast<int>(paths.size());
  int horizon = 0;
  for (const auto& p : paths) horizon = std::max(horizon, static_cast<int>(p->size()));
  int count = 0;
  first->a = kNone;
  owner.assign(num_vertices, kNone);
  stamp.assign(num_vertices, -1);
  std::vector<int> prev_owner(num_vertices, kNone), prev_stamp(num_vertices, -1);
  for (int t = 0; t < horizon; ++t) {
    for (int i = 0; i < n; ++i) {
      const int v = At(*paths[i], t);
      if (stamp[v] == t) {
        ++count;
        if (first->a == kNone) *first = {owner[v], i, v, kNone, t};
      } else {
        stamp[v] = t;
        owner[v] = i;
      }
      if (t == 0) continue;
      const int u = At(*paths[i], t - 1);
      if (u == v || prev_stamp[v] != t - 1) continue;
      const int j = prev_owner[v];
      if (j != i && At(*paths[j], t) == u && i < j) {
        ++count;
        if (first->a == kNone) *first = {i, j, u, v, t};
      }
    }
    for (int i = 0; i < n; ++i) {
      const int v = At(*paths[i], t);
      prev_stamp[v] = t;
      prev_owner[v] = i;
    }
  }
  return count;
}

// Space-time A* for one agent under constraints, breaking ties among equal f by fewer
// conflicts with the other agents' paths (`cat`: occupancy count per (t, v), flat).
class LowLevel {
 public:
  explicit LowLevel(const GridGraph& g) : g_(g) {}

  // Returns an empty path when no path exists within the horizon.
  Path Plan(int start, int goal, DistanceTable& dist,
            const absl::flat_hash_set<int64_t>& vertex_forbidden,
            const absl::flat_hash_set<int64_t>& edge_forbidden, int last_goal_constraint,
            const std::vector<uint16_t>& cat, int cat_horizon) {
    nodes_.clear();
    closed_.clear();
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> open;
    const int horizon = std::max(last_goal_constraint + 1, 0) + g_.size() + 1;
    auto conflicts_at = [&](int v, int t) -> int {
      const int tt = std::min(t, cat_horizon - 1);
      return tt < 0 ? 0 : cat[static_cast<size_t>(tt) * g_.size() + v];
    };
    nodes_.push_back({start, 0, kNone, 0});
    open.push({dist.Get(start), 0, 0, 0});
    closed_[Key(start, 0)] = 0;
    while (!open.empty()) {
      const Entry e = open.top();
      open.pop();
      const Node cur = nodes_[e.id];
      if (cur.v == goal && cur.t > last_goal_constraint) {
        Path path(cur.t + 1);
        for (int id = e.id; id != kNone; id = nodes_[id].parent) path[nodes_[id].t] = nodes_[id].v;
        return path;
      }
      if (cur.t >= horizon || nodes_.size() > kMaxNodes) continue;
      const int t = cur.t + 1;
      for (int k = 0; k <= g_.Degree(cur.v); ++k) {
        const int v = k < g_.Degree(cur.v) ? g_.Neighbor(cur.v, k) : cur.v;
        if (vertex_forbidden.contains(Key(v, t))) continue;
        if (v != cur.v && edge_forbidden.contains(EdgeKey(cur.v, v, t))) continue;
        const int h = dist.Get(v);
        if (h >= DistanceTable::kUnreachable) continue;
        const int64_t key = Key(v, t);
        const int c = cur.conflicts + conflicts_at(v, t);
        auto it = closed_.find(key);
        if (it != closed_.end() && nodes_[it->second].conflicts <= c) continue;
        const int id = static_cast<int>(nodes_.size());
        nodes_.push_back({v, t, e.id, c});
        closed_[key] = id;
        open.push({t + h, c, -t, id});
      }
    }
    return {};
  }

 private:
  struct Node {
    int v;
    int t;
    int parent;
    int conflicts;
  };
  struct Entry {
    int f;
    int conflicts;
    int neg_g;
    int id;
    bool operator>(const Entry& o) const {
      return std::tie(f, conflicts, neg_g, id) > std::tie(o.f, o.conflicts, o.neg_g, o.id);
    }
  };
  static constexpr size_t kMaxNodes = 4'000'000;
  const GridGraph& g_;
  std::vector<Node> nodes_;
  absl::flat_hash_map<int64_t, int> closed_;
};

}  // namespace

absl::Status EecbsParams::Validate() const {
  if (!(suboptimality >= 1.0) || !std::isfinite(suboptimality)) {
    return absl::InvalidArgumentError("suboptimality: must be finite and >= 1");
  }
  if (!(time_limit_s > 0.0) || !std::isfinite(time_limit_s)) {
    return absl::InvalidArgumentError("time_limit_s: must be finite and > 0");
  }
  if (max_high_level_nodes <= 0) {
    return absl::InvalidArgumentError("max_high_level_nodes: must be > 0");
  }
  return absl::OkStatus();
}

EecbsSolver::EecbsSolver(const MapfInstance& instance, const EecbsParams& params)
    : instance_(instance), params_(params) {}

absl::StatusOr<MapfResult> EecbsSolver::Solve(std::stop_token stop) {
  if (absl::Status s = params_.Validate(); !s.ok()) return s;
  if (absl::Status s = instance_.Validate(); !s.ok()) return s;
  using Clock = std::chrono::steady_clock;
  const Clock::time_point t0 = Clock::now();
  auto elapsed_ms = [&] {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  };
  const GridGraph& g = *instance_.graph;
  const int n = instance_.num_agents();
  const int nv = g.size();
  std::vector<DistanceTable> dist;
  dist.reserve(n);
  for (int i = 0; i < n; ++i) dist.emplace_back(g, instance_.goals[i]);
  LowLevel low(g);
  std::vector<int> owner, stamp;
  std::vector<uint16_t> cat;
  int cat_horizon = 0;

  auto build_cat = [&](const std::vector<std::shared_ptr<const Path>>& paths, int skip) {
    cat_horizon = 1;
    for (const auto& p : paths) {
      if (p) cat_horizon = std::max(cat_horizon, static_cast<int>(p->size()) + 1);
    }
    cat.assign(static_cast<size_t>(cat_horizon) * nv, 0);
    for (int i = 0; i < static_cast<int>(paths.size()); ++i) {
      if (i == skip || !paths[i]) continue;
      for (int t = 0; t < cat_horizon; ++t) {
        uint16_t& c = cat[static_cast<size_t>(t) * nv + At(*paths[i], t)];
        if (c < 65535) ++c;
      }
    }
  };
  auto path_cost = [&](const Path& p, int i) { return PathCost(p, instance_.goals[i]); };

  std::vector<CtNode> tree;
  // Root: plan agents one by one, each avoiding the conflicts of those already planned.
  {
    CtNode root{kNone, {kNone, kNone, kNone, 0}, std::vector<std::shared_ptr<const Path>>(n), 0, 0,
                {}};
    const absl::flat_hash_set<int64_t> none;
    for (int i = 0; i < n; ++i) {
      build_cat(root.paths, i);
      Path p = low.Plan(instance_.starts[i], instance_.goals[i], dist[i], none, none, -1, cat,
                        cat_horizon);
      if (p.empty()) return absl::NotFoundError(absl::StrCat("eecbs: agent ", i, " has no path"));
      root.cost += path_cost(p, i);
      root.paths[i] = std::make_shared<const Path>(std::move(p));
    }
    root.conflicts = CountConflicts(root.paths, nv, owner, stamp, &root.first);
    tree.push_back(std::move(root));
  }

  // OPEN by cost, FOCAL (cost ≤ w · min cost) by conflicts.
  std::set<std::pair<int64_t, int>> open;
  std::set<std::tuple<int, int64_t, int>> focal;
  open.insert({tree[0].cost, 0});
  focal.insert({tree[0].conflicts, tree[0].cost, 0});
  int64_t focal_bound_cost = tree[0].cost;
  MapfResult result;
  result.solver = "eecbs";

  while (!open.empty()) {
    if (stop.stop_requested()) return absl::CancelledError("eecbs: stopped before a plan");
    if (elapsed_ms() > params_.time_limit_s * 1000.0) {
      return absl::DeadlineExceededError(
          absl::StrCat("eecbs: no plan within ", params_.time_limit_s, " s"));
    }
    if (static_cast<int>(tree.size()) > params_.max_high_level_nodes) {
      return absl::ResourceExhaustedError("eecbs: high-level node cap reached");
    }
    // Grow FOCAL when the lowest open cost rose.
    const int64_t lb = open.begin()->first;
    const int64_t bound = static_cast<int64_t>(std::floor(params_.suboptimality * lb + 1e-9));
    if (bound > focal_bound_cost) {
      for (auto it = open.lower_bound({focal_bound_cost + 1, -1});
           it != open.end() && it->first <= bound; ++it) {
        focal.insert({tree[it->second].conflicts, it->first, it->second});
      }
      focal_bound_cost = bound;
    }
    if (focal.empty()) {
      // Every open node is above the bound; take the cheapest.
      const int id = open.begin()->second;
      focal.insert({tree[id].conflicts, tree[id].cost, id});
    }
    const int id = std::get<2>(*focal.begin());
    focal.erase(focal.begin());
    open.erase({tree[id].cost, id});
    ++result.expanded_nodes;
    if (tree[id].conflicts == 0) {
      result.solution.paths.resize(n);
      for (int i = 0; i < n; ++i) result.solution.paths[i] = *tree[id].paths[i];
      result.first_solution_ms = result.final_ms = elapsed_ms();
      return result;
    }
    const Conflict c = tree[id].first;
    for (int side = 0; side < 2; ++side) {
      Constraint con;
      if (c.v == kNone) {
        con = {side == 0 ? c.a : c.b, kNone, c.u, c.t};
      } else {
        con = side == 0 ? Constraint{c.a, c.u, c.v, c.t} : Constraint{c.b, c.v, c.u, c.t};
      }
      const int agent = con.agent;
      absl::flat_hash_set<int64_t> vertex_forbidden, edge_forbidden;
      int last_goal_constraint = -1;
      auto add = [&](const Constraint& k) {
        if (k.agent != agent) return;
        if (k.from == kNone) {
          vertex_forbidden.insert(Key(k.to, k.t));
          if (k.to == instance_.goals[agent]) {
            last_goal_constraint = std::max(last_goal_constraint, k.t);
          }
        } else {
          edge_forbidden.insert(EdgeKey(k.from, k.to, k.t));
        }
      };
      add(con);
      for (int a = id; a != kNone && tree[a].parent != kNone; a = tree[a].parent) {
        add(tree[a].constraint);
      }
      build_cat(tree[id].paths, agent);
      Path p = low.Plan(instance_.starts[agent], instance_.goals[agent], dist[agent],
                        vertex_forbidden, edge_forbidden, last_goal_constraint, cat, cat_horizon);
      if (p.empty()) continue;
      CtNode child{id, con, tree[id].paths, tree[id].cost, 0, {}};
      child.cost += path_cost(p, agent) - path_cost(*child.paths[agent], agent);
      child.paths[agent] = std::make_shared<const Path>(std::move(p));
      child.conflicts = CountConflicts(child.paths, nv, owner, stamp, &child.first);
      const int child_id = static_cast<int>(tree.size());
      tree.push_back(std::move(child));
      open.insert({tree[child_id].cost, child_id});
      if (tree[child_id].cost <= focal_bound_cost) {
        focal.insert({tree[child_id].conflicts, tree[child_id].cost, child_id});
      }
    }
  }
  return absl::NotFoundError("eecbs: no plan exists");
}

}  // namespace fleetnav::planner
