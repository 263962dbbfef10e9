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
  int64_t cost;         // sum of path costs
  std::vector<int> lb;  // per agent: lower bound of its optimal cost under the constraints
  int64_t lb_sum;
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

// Focal space-time search for one agent under constraints (the low level of ECBS/EECBS):
// OPEN holds every generated node by f = t + h; FOCAL holds those with f ≤ w · f_min, ordered
// by the number of conflicts with the other agents' paths (`cat`: occupancy count per (t, v),
// flat), then f. The path's length is at most w times the optimal one under the constraints,
// and `lower_bound` (the lowest f in OPEN when the goal is taken) bounds the optimum below.
class LowLevel {
 public:
  explicit LowLevel(const GridGraph& g) : g_(g) {}

  struct Result {
    Path path;  // empty when no path exists within the horizon
    int lower_bound = 0;
  };

  Result Plan(int start, int goal, double w, DistanceTable& dist,
              const absl::flat_hash_set<int64_t>& vertex_forbidden,
              const absl::flat_hash_set<int64_t>& edge_forbidden, int last_goal_constraint,
              const std::vector<uint16_t>& cat, int cat_horizon) {
    nodes_.clear();
    closed_.clear();
    ++generation_;
    std::priority_queue<OpenEntry, std::vector<OpenEntry>, std::greater<OpenEntry>> open;
    std::priority_queue<OpenEntry, std::vector<OpenEntry>, std::greater<OpenEntry>> pending;
    std::priority_queue<FocalEntry, std::vector<FocalEntry>, std::greater<FocalEntry>> focal;
    const int horizon = std::max(last_goal_constraint + 1, 0) + g_.size() + 1;
    auto conflicts_at = [&](int v, int t) -> int {
      const int tt = std::min(t, cat_horizon - 1);
      return tt < 0 ? 0 : cat[static_cast<size_t>(tt) * g_.size() + v];
    };
    // Closed table: dense (t, v) slots with generation stamps when small enough, else hashed.
    const size_t dense_size = static_cast<size_t>(horizon + 2) * g_.size();
    const bool dense = dense_size <= kMaxDenseSlots;
    if (dense && slot_.size() < dense_size) {
      slot_.resize(dense_size);
      stamp_.resize(dense_size, 0);
    }
    auto find_closed = [&](int v, int t) -> int {
      if (dense) {
        const size_t k = static_cast<size_t>(t) * g_.size() + v;
        return stamp_[k] == generation_ ? slot_[k] : kNone;
      }
      auto it = closed_.find(Key(v, t));
      return it == closed_.end() ? kNone : it->second;
    };
    auto set_closed = [&](int v, int t, int id) {
      if (dense) {
        const size_t k = static_cast<size_t>(t) * g_.size() + v;
        stamp_[k] = generation_;
        slot_[k] = id;
      } else {
        closed_[Key(v, t)] = id;
      }
    };
    const int f0 = std::max(dist.Get(start), last_goal_constraint + 1);
    double bound = w * f0;
    auto push = [&](int id) {
      const Node& n = nodes_[id];
      open.push({n.f, id});
      if (n.f <= bound) {
        focal.push({n.conflicts, n.f, -n.t, id});
      } else {
        pending.push({n.f, id});
      }
    };
    nodes_.push_back({start, 0, kNone, 0, dist.Get(start), false});
    set_closed(start, 0, 0);
    push(0);
    while (true) {
      while (!open.empty() && nodes_[open.top().id].expanded) open.pop();
      if (open.empty()) return {};
      const int f_min = open.top().f;
      if (w * f_min > bound) bound = w * f_min;
      while (!pending.empty() && pending.top().f <= bound) {
        const int id = pending.top().id;
        pending.pop();
        if (!nodes_[id].expanded)
          focal.push({nodes_[id].conflicts, nodes_[id].f, -nodes_[id].t, id});
      }
      while (!focal.empty() && nodes_[focal.top().id].expanded) focal.pop();
      if (focal.empty()) return {};
      const int id = focal.top().id;
      focal.pop();
      nodes_[id].expanded = true;
      const Node cur = nodes_[id];
      if (cur.v == goal && cur.t > last_goal_constraint) {
        Result r;
        r.path.resize(cur.t + 1);
        for (int k = id; k != kNone; k = nodes_[k].parent) r.path[nodes_[k].t] = nodes_[k].v;
        r.lower_bound = std::max(f_min, f0);
        return r;
      }
      if (cur.t >= horizon || nodes_.size() > kMaxNodes) continue;
      const int t = cur.t + 1;
      for (int k = 0; k <= g_.Degree(cur.v); ++k) {
        const int v = k < g_.Degree(cur.v) ? g_.Neighbor(cur.v, k) : cur.v;
        if (vertex_forbidden.contains(Key(v, t))) continue;
        if (v != cur.v && edge_forbidden.contains(EdgeKey(cur.v, v, t))) continue;
        const int h = dist.Get(v);
        if (h >= DistanceTable::kUnreachable) continue;
        const int c = cur.conflicts + conflicts_at(v, t);
        const int known = find_closed(v, t);
        if (known != kNone && nodes_[known].conflicts <= c) continue;
        const int child = static_cast<int>(nodes_.size());
        nodes_.push_back({v, t, id, c, t + h, false});
        // A less conflicting copy supersedes the known one.
        if (known != kNone) nodes_[known].expanded = true;
        set_closed(v, t, child);
        push(child);
      }
    }
  }

 private:
  struct Node {
    int v;
    int t;
    int parent;
    int conflicts;
    int f;
    bool expanded;
  };
  struct OpenEntry {
    int f;
    int id;
    bool operator>(const OpenEntry& o) const { return std::tie(f, id) > std::tie(o.f, o.id); }
  };
  struct FocalEntry {
    int conflicts;
    int f;
    int neg_g;
    int id;
    bool operator>(const FocalEntry& o) const {
      return std::tie(conflicts, f, neg_g, id) > std::tie(o.conflicts, o.f, o.neg_g, o.id);
    }
  };
  static constexpr size_t kMaxNodes = 4'000'000;
  static constexpr size_t kMaxDenseSlots = 16'000'000;
  const GridGraph& g_;
  std::vector<Node> nodes_;
  absl::flat_hash_map<int64_t, int> closed_;
  std::vector<int> slot_;
  std::vector<uint32_t> stamp_;
  uint32_t generation_ = 0;
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

  const double w = params_.suboptimality;
  std::vector<CtNode> tree;
  // Root: plan agents one by one, each avoiding the conflicts of those already planned.
  {
    CtNode root{kNone,
                {kNone, kNone, kNone, 0},
                std::vector<std::shared_ptr<const Path>>(n),
                0,
                std::vector<int>(n, 0),
                0,
                0,
                {}};
    const absl::flat_hash_set<int64_t> none;
    for (int i = 0; i < n; ++i) {
      build_cat(root.paths, i);
      LowLevel::Result r = low.Plan(instance_.starts[i], instance_.goals[i], w, dist[i], none, none,
                                    -1, cat, cat_horizon);
      if (r.path.empty()) {
        return absl::NotFoundError(absl::StrCat("eecbs: agent ", i, " has no path"));
      }
      root.cost += path_cost(r.path, i);
      root.lb[i] = r.lower_bound;
      root.lb_sum += r.lower_bound;
      root.paths[i] = std::make_shared<const Path>(std::move(r.path));
    }
    root.conflicts = CountConflicts(root.paths, nv, owner, stamp, &root.first);
    tree.push_back(std::move(root));
  }

  // OPEN by lower bound; FOCAL holds the nodes whose cost ≤ w · (lowest open bound), by
  // conflicts; WAITING holds the other open nodes by cost until the bound rises to them.
  std::set<std::pair<int64_t, int>> open;
  std::set<std::tuple<int, int64_t, int>> focal;
  std::set<std::pair<int64_t, int>> waiting;
  double focal_bound = -1.0;
  auto insert = [&](int id) {
    open.insert({tree[id].lb_sum, id});
    if (tree[id].cost <= focal_bound) {
      focal.insert({tree[id].conflicts, tree[id].cost, id});
    } else {
      waiting.insert({tree[id].cost, id});
    }
  };
  insert(0);
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
    const double bound = w * static_cast<double>(open.begin()->first);
    if (bound > focal_bound) {
      focal_bound = bound;
      while (!waiting.empty() && static_cast<double>(waiting.begin()->first) <= focal_bound) {
        const int id = waiting.begin()->second;
        waiting.erase(waiting.begin());
        focal.insert({tree[id].conflicts, tree[id].cost, id});
      }
    }
    int id;
    if (!focal.empty()) {
      id = std::get<2>(*focal.begin());
      focal.erase(focal.begin());
    } else {
      id = open.begin()->second;
      waiting.erase({tree[id].cost, id});
    }
    open.erase({tree[id].lb_sum, id});
    ++result.expanded_nodes;
    if (tree[id].conflicts == 0) {
      result.solution.paths.resize(n);
      for (int i = 0; i < n; ++i) result.solution.paths[i] = *tree[id].paths[i];
      result.first_solution_ms = result.final_ms = elapsed_ms();
      return result;
    }
    const Conflict c = tree[id].first;
    bool bypassed = false;
    for (int side = 0; side < 2 && !bypassed; ++side) {
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
      LowLevel::Result r =
          low.Plan(instance_.starts[agent], instance_.goals[agent], w, dist[agent],
                   vertex_forbidden, edge_forbidden, last_goal_constraint, cat, cat_horizon);
      if (r.path.empty()) continue;
      CtNode child{id, con, tree[id].paths, tree[id].cost, tree[id].lb, tree[id].lb_sum, 0, {}};
      child.cost += path_cost(r.path, agent) - path_cost(*child.paths[agent], agent);
      // A child's bound never drops below its parent's for that agent.
      const int agent_lb = std::max(r.lower_bound, child.lb[agent]);
      child.lb_sum += agent_lb - child.lb[agent];
      child.lb[agent] = agent_lb;
      child.paths[agent] = std::make_shared<const Path>(std::move(r.path));
      child.conflicts = CountConflicts(child.paths, nv, owner, stamp, &child.first);
      // Bypass (Boyarski et al., IJCAI 2015, as used by EECBS): a replanned path that costs no
      // more and leaves fewer conflicts also satisfies the parent's constraints, so the parent
      // adopts it instead of branching.
      if (child.cost <= tree[id].cost && child.conflicts < tree[id].conflicts) {
        child.parent = tree[id].parent;
        child.constraint = tree[id].constraint;
        child.lb = tree[id].lb;
        child.lb_sum = tree[id].lb_sum;
        tree[id] = std::move(child);
        insert(id);
        bypassed = true;
        break;
      }
      const int child_id = static_cast<int>(tree.size());
      tree.push_back(std::move(child));
      insert(child_id);
    }
  }
  return absl::NotFoundError("eecbs: no plan exists");
}

}  // namespace fleetnav::planner
