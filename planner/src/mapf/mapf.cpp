#include "fleetnav/planner/mapf/mapf.hpp"

#include <algorithm>
#include <random>

#include "absl/container/flat_hash_map.h"
#include "absl/strings/str_cat.h"

namespace fleetnav::planner {
namespace {

int At(const std::vector<int>& path, size_t t) { return t < path.size() ? path[t] : path.back(); }

}  // namespace

absl::Status MapfInstance::Validate() const {
  if (graph == nullptr) return absl::InvalidArgumentError("graph: null");
  if (starts.size() != goals.size()) {
    return absl::InvalidArgumentError("starts and goals: sizes differ");
  }
  absl::flat_hash_map<int, int> start_owner, goal_owner;
  for (int i = 0; i < num_agents(); ++i) {
    if (starts[i] < 0 || starts[i] >= graph->size()) {
      return absl::InvalidArgumentError(absl::StrCat("starts[", i, "]: not a free vertex"));
    }
    if (goals[i] < 0 || goals[i] >= graph->size()) {
      return absl::InvalidArgumentError(absl::StrCat("goals[", i, "]: not a free vertex"));
    }
    if (auto [it, inserted] = start_owner.emplace(starts[i], i); !inserted) {
      return absl::InvalidArgumentError(
          absl::StrCat("starts[", i, "]: same vertex as starts[", it->second, "]"));
    }
    if (auto [it, inserted] = goal_owner.emplace(goals[i], i); !inserted) {
      return absl::InvalidArgumentError(absl::StrCat(
          "goals[", i, "]: same vertex as goals[", it->second,
          "]; two robots cannot both end on one vertex, give one of them another goal"));
    }
  }
  const std::vector<int> label = graph->ComponentLabels();
  for (int i = 0; i < num_agents(); ++i) {
    if (label[starts[i]] != label[goals[i]]) {
      return absl::InvalidArgumentError(
          absl::StrCat("goals[", i, "]: unreachable from starts[", i, "]"));
    }
  }
  return absl::OkStatus();
}

absl::StatusOr<MapfInstance> InstanceFromScenario(const GridGraph& graph,
                                                  const std::vector<ScenarioEntry>& entries,
                                                  int num_agents) {
  if (num_agents < 0 || num_agents > static_cast<int>(entries.size())) {
    return absl::InvalidArgumentError(
        absl::StrCat("agents: ", num_agents, " requested, scenario has ", entries.size()));
  }
  MapfInstance instance;
  instance.graph = &graph;
  for (int i = 0; i < num_agents; ++i) {
    const ScenarioEntry& e = entries[i];
    const int s = graph.VertexAt(e.start_x, e.start_y);
    const int g = graph.VertexAt(e.goal_x, e.goal_y);
    if (s == GridGraph::kNone || g == GridGraph::kNone) {
      return absl::InvalidArgumentError(
          absl::StrCat("scenario entry ", i, ": start or goal on a blocked cell"));
    }
    instance.starts.push_back(s);
    instance.goals.push_back(g);
  }
  return instance;
}

absl::StatusOr<MapfInstance> RandomInstance(const GridGraph& graph, int num_agents, uint64_t seed) {
  const std::vector<int> label = graph.ComponentLabels();
  std::vector<int> count;
  for (int l : label) {
    if (l >= static_cast<int>(count.size())) count.resize(l + 1, 0);
    ++count[l];
  }
  if (count.empty()) return absl::InvalidArgumentError("map: no free cell");
  const int best = static_cast<int>(std::max_element(count.begin(), count.end()) - count.begin());
  std::vector<int> pool;
  for (int v = 0; v < graph.size(); ++v) {
    if (label[v] == best) pool.push_back(v);
  }
  if (num_agents < 0 || num_agents > static_cast<int>(pool.size())) {
    return absl::InvalidArgumentError(absl::StrCat(
        "agents: ", num_agents, " exceed the largest component (", pool.size(), " cells)"));
  }
  std::mt19937_64 rng(seed);
  MapfInstance instance;
  instance.graph = &graph;
  std::vector<int> shuffled = pool;
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  instance.starts.assign(shuffled.begin(), shuffled.begin() + num_agents);
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  instance.goals.assign(shuffled.begin(), shuffled.begin() + num_agents);
  return instance;
}

int PathCost(const std::vector<int>& path, int goal) {
  for (int t = static_cast<int>(path.size()) - 1; t >= 0; --t) {
    if (path[t] != goal) return t + 1;
  }
  return 0;
}

int64_t SumOfCosts(const MapfInstance& instance, const MapfSolution& solution) {
  int64_t soc = 0;
  for (int i = 0; i < instance.num_agents(); ++i)
    soc += PathCost(solution.paths[i], instance.goals[i]);
  return soc;
}

int Makespan(const MapfInstance& instance, const MapfSolution& solution) {
  int makespan = 0;
  for (int i = 0; i < instance.num_agents(); ++i) {
    makespan = std::max(makespan, PathCost(solution.paths[i], instance.goals[i]));
  }
  return makespan;
}

int64_t SumOfCostsLowerBound(const MapfInstance& instance) {
  int64_t lb = 0;
  for (int i = 0; i < instance.num_agents(); ++i) {
    DistanceTable table(*instance.graph, instance.goals[i]);
    lb += table.Get(instance.starts[i]);
  }
  return lb;
}

absl::Status ValidateSolution(const MapfInstance& instance, const MapfSolution& solution) {
  const GridGraph& g = *instance.graph;
  const int n = instance.num_agents();
  if (static_cast<int>(solution.paths.size()) != n) {
    return absl::InvalidArgumentError(
        absl::StrCat("solution has ", solution.paths.size(), " paths for ", n, " agents"));
  }
  size_t horizon = 0;
  for (int i = 0; i < n; ++i) {
    const std::vector<int>& p = solution.paths[i];
    if (p.empty()) return absl::InvalidArgumentError(absl::StrCat("agent ", i, ": empty path"));
    if (p.front() != instance.starts[i]) {
      return absl::InvalidArgumentError(absl::StrCat("agent ", i, ": does not start at its start"));
    }
    if (p.back() != instance.goals[i]) {
      return absl::InvalidArgumentError(absl::StrCat("agent ", i, ": does not end at its goal"));
    }
    for (size_t t = 0; t < p.size(); ++t) {
      if (p[t] < 0 || p[t] >= g.size()) {
        return absl::InvalidArgumentError(absl::StrCat("agent ", i, " step ", t, ": bad vertex"));
      }
      if (t > 0 && p[t] != p[t - 1] && !g.Adjacent(p[t - 1], p[t])) {
        return absl::InvalidArgumentError(absl::StrCat("agent ", i, " step ", t, ": jump from (",
                                                       g.X(p[t - 1]), ",", g.Y(p[t - 1]), ") to (",
                                                       g.X(p[t]), ",", g.Y(p[t]), ")"));
      }
    }
    horizon = std::max(horizon, p.size());
  }
  // owner[v] is the agent at v at step stamp[v]; prev_* hold the same for the step before.
  std::vector<int> owner(g.size(), -1), stamp(g.size(), -1);
  std::vector<int> prev_owner(g.size(), -1), prev_stamp(g.size(), -1);
  for (size_t t = 0; t < horizon; ++t) {
    const int ti = static_cast<int>(t);
    for (int i = 0; i < n; ++i) {
      const int v = At(solution.paths[i], t);
      if (stamp[v] == ti) {
        return absl::InvalidArgumentError(absl::StrCat("vertex conflict: agents ", owner[v],
                                                       " and ", i, " at (", g.X(v), ",", g.Y(v),
                                                       ") at step ", t));
      }
      stamp[v] = ti;
      owner[v] = i;
      if (t == 0) continue;
      // Edge conflict: i moves u -> v while the agent that was at v moves v -> u.
      const int u = At(solution.paths[i], t - 1);
      if (u == v || prev_stamp[v] != ti - 1) continue;
      const int j = prev_owner[v];
      if (At(solution.paths[j], t) == u) {
        return absl::InvalidArgumentError(absl::StrCat("edge conflict: agents ", std::min(i, j),
                                                       " and ", std::max(i, j), " swap at step ",
                                                       t));
      }
    }
    for (int i = 0; i < n; ++i) {
      const int v = At(solution.paths[i], t);
      prev_stamp[v] = ti;
      prev_owner[v] = i;
    }
  }
  return absl::OkStatus();
}

std::string FormatPaths(const GridGraph& graph, const MapfSolution& solution) {
  std::string out;
  for (size_t i = 0; i < solution.paths.size(); ++i) {
    absl::StrAppend(&out, i, ":");
    for (int v : solution.paths[i]) absl::StrAppend(&out, " ", graph.X(v), ",", graph.Y(v));
    out += '\n';
  }
  return out;
}

}  // namespace fleetnav::planner
