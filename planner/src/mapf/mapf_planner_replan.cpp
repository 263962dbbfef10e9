// MapfPlanner::Replan: a new plan from the robots' current positions that keeps what each
// robot has already committed to.
#include <algorithm>
#include <memory>
#include <random>

#include "absl/container/flat_hash_map.h"
#include "absl/strings/str_cat.h"
#include "fleetnav/planner/mapf/constraint_table.hpp"
#include "fleetnav/planner/mapf/mapf_planner.hpp"
#include "fleetnav/planner/mapf/sipp.hpp"

namespace fleetnav::planner {
namespace {

// InvalidArgument naming the prefix that does not start at its robot's position, is not a
// sequence of moves, or meets another prefix (same vertex at one step, or a swap).
absl::Status ValidatePrefixes(const MapfInstance& instance,
                              const std::vector<std::vector<int>>& committed) {
  const GridGraph& g = *instance.graph;
  const int n = instance.num_agents();
  if (static_cast<int>(committed.size()) != n) {
    return absl::InvalidArgumentError(
        absl::StrCat("committed: ", committed.size(), " prefixes for ", n, " robots"));
  }
  absl::flat_hash_map<std::pair<int, int>, int> at;  // (vertex, step) → robot
  for (int i = 0; i < n; ++i) {
    const std::vector<int>& p = committed[i];
    const std::string field = absl::StrCat("committed[", i, "]");
    if (p.empty() || p[0] != instance.starts[i]) {
      return absl::InvalidArgumentError(
          absl::StrCat(field, ": must start at the robot's vertex ", instance.starts[i]));
    }
    for (size_t k = 0; k < p.size(); ++k) {
      if (p[k] < 0 || p[k] >= g.size()) {
        return absl::InvalidArgumentError(absl::StrCat(field, "[", k, "]: no such vertex"));
      }
      if (k > 0 && p[k] != p[k - 1] && !g.Adjacent(p[k - 1], p[k])) {
        return absl::InvalidArgumentError(absl::StrCat(field, "[", k, "]: not a move"));
      }
      auto [it, fresh] = at.emplace(std::make_pair(p[k], static_cast<int>(k)), i);
      if (!fresh) {
        return absl::InvalidArgumentError(absl::StrCat(field, " and committed[", it->second,
                                                       "] meet at vertex ", p[k], " step ", k));
      }
    }
  }
  for (int i = 0; i < n; ++i) {
    const std::vector<int>& p = committed[i];
    for (size_t k = 1; k < p.size(); ++k) {
      auto it = at.find({p[k - 1], static_cast<int>(k)});
      if (p[k] == p[k - 1] || it == at.end()) continue;
      const std::vector<int>& q = committed[it->second];
      if (q[k - 1] == p[k]) {
        return absl::InvalidArgumentError(
            absl::StrCat("committed[", i, "] and committed[", it->second, "] swap at step ", k));
      }
    }
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<MapfResult> MapfPlanner::Replan(const MapfInstance& requested,
                                               const std::vector<std::vector<int>>& committed,
                                               const MapfStopCondition& stop) {
  absl::StatusOr<MapfInstance> prepared = Prepare(requested, stop);
  if (!prepared.ok()) return prepared.status();
  const MapfInstance& instance = *prepared;
  if (absl::Status s = ValidatePrefixes(instance, committed); !s.ok()) return s;
  const MapfStopwatch watch(stop);
  const int n = instance.num_agents();
  const GridGraph& g = *instance.graph;
  std::vector<std::unique_ptr<DistanceTable>> dist(n);
  for (int i = 0; i < n; ++i) dist[i] = std::make_unique<DistanceTable>(g, instance.goals[i]);
  std::vector<int> order(n);
  for (int i = 0; i < n; ++i) order[i] = i;
  // First order: the robots farthest from their goals first; later ones random.
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return dist[a]->Get(committed[a].back()) > dist[b]->Get(committed[b].back());
  });
  std::mt19937_64 rng(params_.seed);
  ConstraintTable table(g.size());
  SippPlanner sipp(g);
  MapfResult result;
  result.solver = "prioritized";
  result.planned_goals = instance.goals;
  // 1. Prioritized planning over random orders, for half the budget.
  bool found = false;
  int attempt = 0;
  for (; !found && watch.ElapsedMs() < 500.0 * stop.time_limit_s; ++attempt) {
    if (watch.StopRequested()) return absl::CancelledError("replan: stopped before a plan");
    // Orders alternate between two forms of prioritized planning: revised (robots not yet
    // planned hold the end of their prefix for ever, so nobody is planned through them) and
    // plain (they are invisible after their prefix). Neither is complete alone.
    const bool revised = attempt % 2 == 0;
    if (attempt > 1) std::shuffle(order.begin(), order.end(), rng);
    table.Clear();
    for (int i = 0; i < n; ++i) table.AddHardPath(committed[i], 0, /*park=*/revised);
    std::vector<std::vector<int>> paths(n);
    bool ok = true;
    for (int i : order) {
      table.RemoveHardPath(committed[i], 0, /*park=*/revised);
      const int prefix_end = static_cast<int>(committed[i].size()) - 1;
      SippRequest request;
      request.start = committed[i].back();
      request.goal = instance.goals[i];
      request.start_step = prefix_end;
      request.no_following = params_.forbid_rotations;
      absl::StatusOr<SippResult> r = sipp.Plan(request, table, *dist[i]);
      if (!r.ok()) {
        ok = false;
        break;
      }
      table.AddHardPath(committed[i], 0, /*park=*/false);
      table.AddHardPath(r->path, prefix_end, /*park=*/true);
      paths[i].assign(committed[i].begin(), committed[i].end() - 1);
      paths[i].insert(paths[i].end(), r->path.begin(), r->path.end());
    }
    if (!ok) continue;
    result.solution.paths = std::move(paths);
    found = true;
  }

  // 2. Otherwise, if the prefixes padded with waits to one length still fit together, a whole
  //    multi-robot plan (Solve, complete) from where they end, behind them.
  std::string fallback = "prefixes of different lengths do not fit together padded";
  if (!found) {
    size_t length = 0;
    for (const auto& p : committed) length = std::max(length, p.size());
    std::vector<std::vector<int>> padded = committed;
    for (auto& p : padded) p.resize(length, p.back());
    if (ValidatePrefixes(instance, padded).ok()) {
      MapfInstance from_ends = instance;
      for (int i = 0; i < n; ++i) from_ends.starts[i] = padded[i].back();
      MapfPlannerParams rest = params_;
      rest.anytime = false;
      absl::StatusOr<MapfResult> plan = MapfPlanner(rest).Solve(from_ends, watch.Remaining());
      if (plan.ok()) {
        result.solution.paths.resize(n);
        for (int i = 0; i < n; ++i) {
          result.solution.paths[i].assign(padded[i].begin(), padded[i].end() - 1);
          const std::vector<int>& tail = plan->solution.paths[i];
          result.solution.paths[i].insert(result.solution.paths[i].end(), tail.begin(), tail.end());
        }
        result.solver = "prioritized-failed+" + plan->solver;
        found = true;
      } else {
        fallback = std::string(plan.status().message());
      }
    }
  }
  if (!found) {
    if (watch.StopRequested()) return absl::CancelledError("replan: stopped before a plan");
    return absl::DeadlineExceededError(
        absl::StrCat("replan: no plan keeping the committed prefixes within ", stop.time_limit_s,
                     " s (", attempt, " priority orders tried; then ", fallback, ")"));
  }
  result.first_solution_ms = result.final_ms = watch.ElapsedMs();

  std::vector<int> fixed(n);
  for (int i = 0; i < n; ++i) fixed[i] = static_cast<int>(committed[i].size());
  if (absl::Status st = RepairAndRefine(instance, fixed, watch, nullptr, &result); !st.ok())
    return st;
  return result;
}

}  // namespace fleetnav::planner
