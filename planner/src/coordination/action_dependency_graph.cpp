#include "fleetnav/planner/coordination/action_dependency_graph.hpp"

#include <algorithm>

#include "absl/strings/str_cat.h"

namespace fleetnav::planner {
namespace {

// A stay of one robot on one vertex: it arrives with action `enter` (-1: it starts there)
// at step `arrive` and leaves with action `leave` (-1: it never leaves).
struct Visit {
  int arrive;
  int agent;
  int enter;
  int leave;
};

}  // namespace

absl::StatusOr<ActionDependencyGraph> ActionDependencyGraph::Compile(const MapfInstance& instance,
                                                                     const MapfSolution& solution) {
  if (absl::Status s = ValidateSolution(instance, solution); !s.ok()) return s;
  ActionDependencyGraph adg;
  const int n = instance.num_agents();
  adg.by_agent_.resize(n);
  std::vector<std::vector<Visit>> visits(instance.graph->size());
  for (int i = 0; i < n; ++i) {
    const std::vector<int>& p = solution.paths[i];
    visits[p[0]].push_back({0, i, -1, -1});
    for (size_t t = 1; t < p.size(); ++t) {
      if (p[t] == p[t - 1]) continue;
      const int id = static_cast<int>(adg.actions_.size());
      adg.actions_.push_back({i, p[t - 1], p[t], static_cast<int>(t)});
      adg.deps_.emplace_back();
      if (!adg.by_agent_[i].empty()) adg.deps_[id].push_back(adg.by_agent_[i].back());
      adg.by_agent_[i].push_back(id);
      visits[p[t - 1]].back().leave = id;
      visits[p[t]].push_back({static_cast<int>(t), i, id, -1});
    }
  }
  // Type 2: entering a vertex waits for the previous visitor's move out of it.
  for (std::vector<Visit>& list : visits) {
    std::sort(list.begin(), list.end(), [](const Visit& a, const Visit& b) {
      return a.arrive < b.arrive || (a.arrive == b.arrive && a.agent < b.agent);
    });
    for (size_t k = 1; k < list.size(); ++k) {
      const Visit& before = list[k - 1];
      const Visit& after = list[k];
      if (before.agent == after.agent) continue;
      // A valid plan has the earlier visitor leave (or it would be a vertex conflict), and
      // the later one arrive by a move (only one robot starts on a vertex).
      adg.deps_[after.enter].push_back(before.leave);
      ++adg.cross_;
    }
  }
  // Rotations show up as cycles; find one with an iterative three-colour DFS.
  const int m = adg.num_actions();
  std::vector<uint8_t> colour(m, 0);
  std::vector<std::pair<int, size_t>> stack;
  for (int s = 0; s < m; ++s) {
    if (colour[s] != 0) continue;
    stack.push_back({s, 0});
    colour[s] = 1;
    while (!stack.empty()) {
      auto& [a, k] = stack.back();
      if (k < adg.deps_[a].size()) {
        const int b = adg.deps_[a][k++];
        if (colour[b] == 1) {
          return absl::FailedPreconditionError(absl::StrCat(
              "plan has a rotation (cyclic dependencies) involving agents ", adg.actions_[a].agent,
              " and ", adg.actions_[b].agent, " at step ", adg.actions_[b].planned_step));
        }
        if (colour[b] == 0) {
          colour[b] = 1;
          stack.push_back({b, 0});
        }
      } else {
        colour[a] = 2;
        stack.pop_back();
      }
    }
  }
  return adg;
}

}  // namespace fleetnav::planner
