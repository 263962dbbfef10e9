#include "fleetnav/planner/coordination/kinematic_dependency_graph.hpp"

#include <algorithm>
#include <map>

namespace fleetnav::planner {
namespace {

constexpr int kNoAction = -1;  // covering from the start, or never releasing (parked)

// One stretch of half steps in which a robot covers a cell, with the action that starts it
// and the action that ends it.
struct Episode {
  int first_half_step;
  int robot;
  int acquire;
  int release;
};

}  // namespace

absl::StatusOr<KinematicDependencyGraph> KinematicDependencyGraph::Compile(
    const KinematicMapfProblem& problem, const KinematicMapfPlan& plan) {
  if (absl::Status s = ValidateKinematicPlan(problem, plan); !s.ok()) return s;
  KinematicDependencyGraph g;
  const int n = static_cast<int>(problem.robots.size());
  g.graph_ = DependencyGraph(n);
  // Per cell, the episodes of every robot, built robot by robot along the half steps: state t
  // at 2t, the move from t to t + 1 at 2t + 1 (covering both footprints).
  std::map<int, std::vector<Episode>> episodes;
  std::vector<int> here, next, during;
  for (int r = 0; r < n; ++r) {
    const std::vector<GridState>& states = plan.states[r];
    const GridMotionModel& motion = problem.robots[r].motion;
    std::map<int, Episode> open;  // cell → episode in progress
    int action_of_step = kNoAction;
    for (size_t t = 0; t < states.size(); ++t) {
      CoveredCells(*problem.map, motion, states[t], &here);
      const bool last = t + 1 == states.size();
      const bool moves = !last && !(states[t + 1] == states[t]);
      int action = kNoAction;
      if (moves) {
        action = g.graph_.AddAction(r);
        g.actions_.push_back({r, states[t], states[t + 1], static_cast<int>(t) + 1});
        CoveredCells(*problem.map, motion, states[t + 1], &next);
      }
      // Cells covered at this state: begun by the action that arrived here (or the start).
      for (int c : here) {
        if (!open.contains(c)) open[c] = {2 * static_cast<int>(t), r, action_of_step, kNoAction};
      }
      if (!moves) continue;
      // The move covers the next footprint too; cells of this footprint that the next one does
      // not cover are released by this action.
      for (int c : next) {
        if (!open.contains(c)) open[c] = {2 * static_cast<int>(t) + 1, r, action, kNoAction};
      }
      for (auto it = open.begin(); it != open.end();) {
        if (std::find(next.begin(), next.end(), it->first) == next.end()) {
          it->second.release = action;
          episodes[it->first].push_back(it->second);
          it = open.erase(it);
        } else {
          ++it;
        }
      }
      action_of_step = action;
    }
    for (auto& [cell, e] : open) episodes[cell].push_back(e);  // parked for ever
  }
  // Type 2: on each cell, the next robot starts covering it only after the previous one left.
  for (auto& [cell, list] : episodes) {
    std::sort(list.begin(), list.end(), [](const Episode& a, const Episode& b) {
      return a.first_half_step < b.first_half_step;
    });
    for (size_t k = 1; k < list.size(); ++k) {
      const Episode& before = list[k - 1];
      const Episode& after = list[k];
      if (before.robot == after.robot || after.acquire == kNoAction ||
          before.release == kNoAction) {
        continue;  // the same robot's order, or impossible in a validated plan
      }
      g.graph_.AddCrossDependency(before.release, after.acquire);
    }
  }
  return g;
}

}  // namespace fleetnav::planner
