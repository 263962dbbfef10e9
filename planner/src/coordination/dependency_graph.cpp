#include "fleetnav/planner/coordination/dependency_graph.hpp"

#include <algorithm>
#include <cstdint>
#include <utility>

#include "absl/strings/str_cat.h"

namespace fleetnav::planner {

int DependencyGraph::AddAction(int robot) {
  const int id = num_actions();
  robot_of_.push_back(robot);
  index_in_robot_.push_back(static_cast<int>(by_robot_[robot].size()));
  by_robot_[robot].push_back(id);
  cross_deps_.emplace_back();
  return id;
}

bool DependencyGraph::AddCrossDependency(int before, int after) {
  if (robot_of_[before] == robot_of_[after]) return false;
  std::vector<int>& deps = cross_deps_[after];
  if (std::find(deps.begin(), deps.end(), before) != deps.end()) return false;
  deps.push_back(before);
  ++cross_;
  return true;
}

std::vector<int> DependencyGraph::DependenciesOf(int id) const {
  std::vector<int> out;
  out.reserve(cross_deps_[id].size() + 1);
  if (index_in_robot_[id] > 0) out.push_back(by_robot_[robot_of_[id]][index_in_robot_[id] - 1]);
  out.insert(out.end(), cross_deps_[id].begin(), cross_deps_[id].end());
  return out;
}

absl::Status DependencyGraph::CheckAcyclic() const {
  // Iterative three-colour depth-first search over "waits for" edges.
  const int m = num_actions();
  std::vector<uint8_t> colour(m, 0);  // 0 unseen, 1 on the stack, 2 done
  std::vector<std::pair<int, std::vector<int>>> stack;
  std::vector<size_t> next;
  for (int s = 0; s < m; ++s) {
    if (colour[s] != 0) continue;
    stack.push_back({s, DependenciesOf(s)});
    next.push_back(0);
    colour[s] = 1;
    while (!stack.empty()) {
      const int a = stack.back().first;
      if (next.back() < stack.back().second.size()) {
        const int b = stack.back().second[next.back()++];
        if (colour[b] == 1) {
          return absl::FailedPreconditionError(absl::StrCat("cyclic dependencies: robots ",
                                                            robot_of_[a], " and ", robot_of_[b],
                                                            " would wait for each other for ever"));
        }
        if (colour[b] == 0) {
          colour[b] = 1;
          stack.push_back({b, DependenciesOf(b)});
          next.push_back(0);
        }
      } else {
        colour[a] = 2;
        stack.pop_back();
        next.pop_back();
      }
    }
  }
  return absl::OkStatus();
}

}  // namespace fleetnav::planner
