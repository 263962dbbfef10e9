#include "fleetnav/planner/coordination/wait_cycles.hpp"

#include <algorithm>
#include <functional>
#include <map>

namespace fleetnav::planner {

std::vector<std::vector<std::string>> FindWaitCycles(
    const std::vector<TrafficClearanceDecision>& decisions) {
  const int n = static_cast<int>(decisions.size());
  std::map<std::string, int> index_of;
  for (int i = 0; i < n; ++i) index_of.emplace(decisions[i].robot_id, i);
  std::vector<std::vector<int>> edges(n);
  for (int i = 0; i < n; ++i) {
    for (const TrafficWait& wait : decisions[i].waits) {
      auto blocker = index_of.find(wait.blocker_robot_id);
      if (blocker == index_of.end() || blocker->second == i) continue;
      // It gets there by itself when the action waited for is one it is cleared to do.
      if (wait.blocker_action >= 0 &&
          wait.blocker_action <= decisions[blocker->second].cleared_up_to) {
        continue;
      }
      edges[i].push_back(blocker->second);
    }
  }
  // Tarjan's strongly connected components.
  std::vector<int> order(n, -1), low(n, 0), stack;
  std::vector<bool> on_stack(n, false);
  std::vector<std::vector<int>> components;
  int counter = 0;
  std::function<void(int)> visit = [&](int v) {
    order[v] = low[v] = counter++;
    stack.push_back(v);
    on_stack[v] = true;
    for (int w : edges[v]) {
      if (order[w] < 0) {
        visit(w);
        low[v] = std::min(low[v], low[w]);
      } else if (on_stack[w]) {
        low[v] = std::min(low[v], order[w]);
      }
    }
    if (low[v] != order[v]) return;
    std::vector<int> component;
    int w = -1;
    do {
      w = stack.back();
      stack.pop_back();
      on_stack[w] = false;
      component.push_back(w);
    } while (w != v);
    if (component.size() > 1) components.push_back(std::move(component));
  };
  for (int v = 0; v < n; ++v) {
    if (order[v] < 0) visit(v);
  }
  for (std::vector<int>& component : components) std::sort(component.begin(), component.end());
  std::sort(components.begin(), components.end());
  std::vector<std::vector<std::string>> out;
  for (const std::vector<int>& component : components) {
    std::vector<std::string>& ids = out.emplace_back();
    for (int i : component) ids.push_back(decisions[i].robot_id);
  }
  return out;
}

}  // namespace fleetnav::planner
