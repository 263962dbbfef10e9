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
  adg.graph_ = DependencyGraph(n);
  std::vector<std::vector<Visit>> visits(instance.graph->size());
  for (int i = 0; i < n; ++i) {
    const std::vector<int>& p = solution.paths[i];
    visits[p[0]].push_back({0, i, -1, -1});
    for (size_t t = 1; t < p.size(); ++t) {
      if (p[t] == p[t - 1]) continue;
      const int id = adg.graph_.AddAction(i);
      adg.actions_.push_back({i, p[t - 1], p[t], static_cast<int>(t)});
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
      adg.graph_.AddCrossDependency(before.leave, after.enter);
    }
  }
  // Rotations show up as cycles.
  if (absl::Status acyclic = adg.graph_.CheckAcyclic(); !acyclic.ok()) {
    return absl::FailedPreconditionError(absl::StrCat("plan has a rotation: ", acyclic.message()));
  }
  return adg;
}

}  // namespace fleetnav::planner
