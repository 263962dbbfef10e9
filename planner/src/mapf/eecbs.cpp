#include "fleetnav/planner/mapf/eecbs.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <queue>
#include <set>
#include <tuple>

#include "absl/strings/str_cat.h"
#include "fleetnav/planner/mapf/constraint_table.hpp"
#include "fleetnav/planner/mapf/sipp.hpp"

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

}  // namespace

absl::Status EecbsParams::Validate() const {
  if (!(suboptimality >= 1.0) || !std::isfinite(suboptimality)) {
    return absl::InvalidArgumentError("suboptimality: must be finite and >= 1");
  }
  if (max_high_level_nodes <= 0) {
    return absl::InvalidArgumentError("max_high_level_nodes: must be > 0");
  }
  return absl::OkStatus();
}

absl::StatusOr<MapfResult> EecbsSolver::Solve(const MapfInstance& instance,
                                              const MapfStopCondition& stop,
                                              const MapfPlanObserver& on_plan) {
  if (absl::Status s = params_.Validate(); !s.ok()) return s;
  if (absl::Status s = ValidateSolveInput(instance, stop); !s.ok()) return s;
  const MapfStopwatch watch(stop);
  const GridGraph& g = *instance.graph;
  const int n = instance.num_agents();
  const int nv = g.size();
  std::vector<DistanceTable> dist;
  dist.reserve(n);
  for (int i = 0; i < n; ++i) dist.emplace_back(g, instance.goals[i]);
  SippPlanner sipp(g);
  ConstraintTable table(nv);
  std::vector<int> owner, stamp;
  // The low level: SIPP under the agent's constraints (hard) and the other agents' paths
  // (soft, to be avoided), focal with the same w as the high level.
  auto plan_agent = [&](int agent, const std::vector<std::shared_ptr<const Path>>& paths,
                        const std::vector<Constraint>& constraints) -> absl::StatusOr<SippResult> {
    table.Clear();
    for (const Constraint& k : constraints) {
      if (k.from == kNone) {
        table.AddHardVertex(k.to, k.t);
      } else {
        table.AddHardEdge(k.from, k.to, k.t);
      }
    }
    for (int i = 0; i < static_cast<int>(paths.size()); ++i) {
      if (i != agent && paths[i]) table.AddSoftPath(*paths[i]);
    }
    SippRequest request;
    request.start = instance.starts[agent];
    request.goal = instance.goals[agent];
    request.suboptimality = params_.suboptimality;
    return sipp.Plan(request, table, dist[agent]);
  };

  auto path_cost = [&](const Path& p, int i) { return PathCost(p, instance.goals[i]); };

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
    for (int i = 0; i < n; ++i) {
      absl::StatusOr<SippResult> r = plan_agent(i, root.paths, {});
      if (!r.ok()) {
        return absl::NotFoundError(absl::StrCat("eecbs: agent ", i, " has no path"));
      }
      root.cost += path_cost(r->path, i);
      root.lb[i] = r->lower_bound_step;
      root.lb_sum += r->lower_bound_step;
      root.paths[i] = std::make_shared<const Path>(std::move(r->path));
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
    if (watch.ShouldStop()) return watch.NoPlanStatus("eecbs");
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
      result.first_solution_ms = result.final_ms = watch.ElapsedMs();
      if (on_plan) on_plan(result);
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
      std::vector<Constraint> constraints = {con};
      for (int a = id; a != kNone && tree[a].parent != kNone; a = tree[a].parent) {
        if (tree[a].constraint.agent == agent) constraints.push_back(tree[a].constraint);
      }
      absl::StatusOr<SippResult> r = plan_agent(agent, tree[id].paths, constraints);
      if (!r.ok()) continue;
      const int lower_bound = r->lower_bound_step;
      CtNode child{id, con, tree[id].paths, tree[id].cost, tree[id].lb, tree[id].lb_sum, 0, {}};
      child.cost += path_cost(r->path, agent) - path_cost(*child.paths[agent], agent);
      // A child's bound never drops below its parent's for that agent.
      const int agent_lb = std::max(lower_bound, child.lb[agent]);
      child.lb_sum += agent_lb - child.lb[agent];
      child.lb[agent] = agent_lb;
      child.paths[agent] = std::make_shared<const Path>(std::move(r->path));
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
