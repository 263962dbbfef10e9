#include "fleetnav/planner/traffic_schedule.hpp"

#include <algorithm>
#include <limits>
#include <map>
#include <set>
#include <tuple>
#include <utility>

namespace fleetnav::planner {
namespace {

constexpr int kParked = -1;

/// A dependency: the waiting action can start once `blocker` (route index, or kParked with
/// the parked robot's index in `parked_index`) has finished `blocker_action`.
struct Dependency {
  int blocker_route = kParked;
  int blocker_action = -1;
  int parked_index = -1;
};

using Node = std::pair<int, int>;  // (route index, action index)

struct Graph {
  std::map<Node, std::vector<Dependency>> deps;  // waiting node → what it waits for
};

bool Started(const ScheduledRoute& r) { return r.first_unfinished > 0 || r.cleared_up_to >= 0; }

int Count(const ScheduledRoute& r) { return static_cast<int>(r.action_cells.size()); }

/// The floor a held route's robot stands on: before its first action its start, then the
/// action it is in.
const CellSet& Standing(const ScheduledRoute& r) {
  if (!Started(r) || r.first_unfinished >= Count(r)) {
    return r.first_unfinished >= Count(r) ? r.end_cells : r.start_cells;
  }
  return r.action_cells[r.first_unfinished];
}

Graph Build(const std::vector<ScheduledRoute>& routes, const std::vector<bool>& held,
            const std::vector<ParkedRobot>& parked) {
  Graph g;
  // Parked robots and held routes stand where they are.
  std::vector<std::pair<int, const CellSet*>> standing;
  for (size_t p = 0; p < parked.size(); ++p) standing.emplace_back(static_cast<int>(p), &parked[p].cells);
  for (size_t r = 0; r < routes.size(); ++r) {
    if (held[r]) standing.emplace_back(static_cast<int>(parked.size() + r), &Standing(routes[r]));
  }
  auto key = [&](int r, int k) {
    const double t = k <= routes[r].cleared_up_to ? -std::numeric_limits<double>::infinity()
                                                 : routes[r].action_start_s[k];
    return std::make_tuple(t, r, k);
  };
  for (int r = 0; r < static_cast<int>(routes.size()); ++r) {
    if (held[r]) continue;
    const ScheduledRoute& a = routes[r];
    for (int k = a.first_unfinished; k < Count(a); ++k) {
      for (const auto& [index, cells] : standing) {
        if (a.action_cells[k].Intersects(*cells)) g.deps[{r, k}].push_back({kParked, -1, index});
      }
    }
    for (int s = 0; s < static_cast<int>(routes.size()); ++s) {
      if (s == r || held[s]) continue;
      const ScheduledRoute& b = routes[s];
      std::set<std::pair<Node, Node>> forced;  // (before, after) pairs between r and s
      for (int k = a.first_unfinished; k < Count(a); ++k) {
        // Crossing where b stands before its first action: after that action.
        if (!Started(b) && a.action_cells[k].Intersects(b.start_cells)) {
          g.deps[{r, k}].push_back({s, 0, -1});
          forced.insert({{s, 0}, {r, k}});
        }
        // Crossing where b will stay: before b's last action (unless that is under way).
        const int last = Count(b) - 1;
        if (last > b.cleared_up_to && a.action_cells[k].Intersects(b.end_cells)) {
          g.deps[{s, last}].push_back({r, k, -1});
          forced.insert({{r, k}, {s, last}});
        }
      }
      if (s < r) continue;  // each pair of routes once for the ordinary conflicts
      for (int k = a.first_unfinished; k < Count(a); ++k) {
        for (int l = b.first_unfinished; l < Count(b); ++l) {
          if (!a.action_cells[k].Intersects(b.action_cells[l])) continue;
          const Node x{r, k};
          const Node y{s, l};
          if (forced.count({x, y}) || forced.count({y, x})) continue;
          if (key(r, k) < key(s, l)) {
            g.deps[y].push_back({r, k, -1});
          } else {
            g.deps[x].push_back({s, l, -1});
          }
        }
      }
    }
  }
  return g;
}

/// A route on a cycle of the graph (intra-route edges k → k+1 plus the dependencies), or -1.
int RouteOnCycle(const std::vector<ScheduledRoute>& routes, const std::vector<bool>& held,
                 const Graph& g) {
  // Successors: blocker → waiter, and k → k+1.
  std::map<Node, std::vector<Node>> next;
  for (const auto& [waiter, deps] : g.deps) {
    for (const Dependency& d : deps) {
      if (d.blocker_route != kParked) next[{d.blocker_route, d.blocker_action}].push_back(waiter);
    }
  }
  std::map<Node, int> color;  // 0 new, 1 on stack, 2 done
  for (int r = 0; r < static_cast<int>(routes.size()); ++r) {
    if (held[r]) continue;
    for (int k = routes[r].first_unfinished; k < Count(routes[r]); ++k) {
      if (color[{r, k}] != 0) continue;
      std::vector<std::pair<Node, size_t>> stack{{{r, k}, 0}};
      color[{r, k}] = 1;
      while (!stack.empty()) {
        auto& [node, child] = stack.back();
        std::vector<Node> succ = next[node];
        if (node.second + 1 < Count(routes[node.first])) succ.push_back({node.first, node.second + 1});
        if (child >= succ.size()) {
          color[node] = 2;
          stack.pop_back();
          continue;
        }
        const Node to = succ[child++];
        if (color[to] == 1) {
          // The cycle runs from `to` up the stack: hold its newest route.
          int newest = to.first;
          for (auto it = stack.rbegin(); it != stack.rend() && it->first != to; ++it) {
            const int q = it->first.first;
            if (routes[q].action_start_s.front() > routes[newest].action_start_s.front() ||
                (routes[q].action_start_s.front() == routes[newest].action_start_s.front() && q > newest)) {
              newest = q;
            }
          }
          return newest;
        }
        if (color[to] == 0) {
          color[to] = 1;
          stack.push_back({to, 0});
        }
      }
    }
  }
  return -1;
}

}  // namespace

std::vector<TrafficClearanceDecision> DecideClearances(const std::vector<ScheduledRoute>& routes,
                                                       const std::vector<ParkedRobot>& parked) {
  std::vector<bool> held(routes.size(), false);
  Graph g = Build(routes, held, parked);
  for (int cycle = RouteOnCycle(routes, held, g); cycle >= 0;
       cycle = RouteOnCycle(routes, held, g)) {
    held[cycle] = true;
    g = Build(routes, held, parked);
  }
  std::vector<TrafficClearanceDecision> out;
  for (int r = 0; r < static_cast<int>(routes.size()); ++r) {
    const ScheduledRoute& route = routes[r];
    TrafficClearanceDecision decision{route.robot_id, route.job_id,
                                      std::max(route.cleared_up_to, route.first_unfinished - 1),
                                      {}, static_cast<bool>(held[r])};
    if (held[r]) {
      for (int s = 0; s < static_cast<int>(routes.size()); ++s) {
        if (s != r && !held[s]) decision.waits.push_back({route.robot_id, decision.cleared_up_to + 1, routes[s].robot_id, Count(routes[s]) - 1});
      }
      out.push_back(std::move(decision));
      continue;
    }
    for (int k = decision.cleared_up_to + 1; k < Count(route); ++k) {
      auto it = g.deps.find({r, k});
      if (it != g.deps.end()) {
        for (const Dependency& d : it->second) {
          if (d.blocker_route == kParked) {
            const bool parked_robot = d.parked_index < static_cast<int>(parked.size());
            decision.waits.push_back(
                {route.robot_id, k,
                 parked_robot ? parked[d.parked_index].robot_id
                              : routes[d.parked_index - parked.size()].robot_id,
                 -1});
          } else if (routes[d.blocker_route].first_unfinished <= d.blocker_action) {
            decision.waits.push_back(
                {route.robot_id, k, routes[d.blocker_route].robot_id, d.blocker_action});
          }
        }
      }
      if (!decision.waits.empty()) break;
      decision.cleared_up_to = k;
    }
    out.push_back(std::move(decision));
  }
  return out;
}

}  // namespace fleetnav::planner
