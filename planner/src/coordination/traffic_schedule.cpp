#include "fleetnav/planner/coordination/traffic_schedule.hpp"

#include <algorithm>
#include <functional>
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

/// The routes being ordered, by index, wherever they are held.
class RouteList {
 public:
  explicit RouteList(const std::vector<const ScheduledRoute*>& routes) : routes_(routes) {}
  const ScheduledRoute& operator[](size_t i) const { return *routes_[i]; }
  size_t size() const { return routes_.size(); }

 private:
  const std::vector<const ScheduledRoute*>& routes_;
};

int Count(const ScheduledRoute& r) { return static_cast<int>(r.action_cells.size()); }

/// Where the robot stands now: its start before the first action, else the end of the last
/// finished one.
const CellSet& Standing(const ScheduledRoute& r) {
  if (r.first_unfinished <= 0 || r.action_end_cells.empty()) return r.start_cells;
  return r.action_end_cells[std::min(r.first_unfinished, Count(r)) - 1];
}

/// Of two routes that cannot both go on, the one to hold whole: one its robot has not begun
/// (it stands at its start, so its job can be withdrawn and the robot sent aside) before one
/// part-way through (a robot that has begun cannot drop its job: holding it left two robots
/// facing each other for good in the dense hall); of two alike, the newer (later expected
/// start; the higher index on a tie), so the older always goes on.
int ToHold(const RouteList& routes, int r, int s) {
  if (RouteBegun(routes[r]) != RouteBegun(routes[s])) return RouteBegun(routes[r]) ? s : r;
  const double tr = routes[r].action_start_s.empty() ? 0.0 : routes[r].action_start_s.front();
  const double ts = routes[s].action_start_s.empty() ? 0.0 : routes[s].action_start_s.front();
  return ts > tr || (ts == tr && s > r) ? s : r;
}

using Block = SharedBlock;

/// Whether action i of `a` and action j of `b` are in each other's way: one sweeps the other's
/// region or where the other stands after it.
bool Meet(const ScheduledRoute& a, int i, const ScheduledRoute& b, int j) {
  return a.action_cells[i].Intersects(b.action_cells[j]) ||
         a.action_cells[i].Intersects(b.action_end_cells[j]) ||
         a.action_end_cells[i].Intersects(b.action_cells[j]);
}

/// The blocks of two routes: 4-connected components of unfinished action pairs that meet.
std::vector<Block> Blocks(const ScheduledRoute& a, const ScheduledRoute& b) {
  const int fa = a.first_unfinished;
  const int fb = b.first_unfinished;
  const int na = std::max(0, Count(a) - fa);
  const int nb = std::max(0, Count(b) - fb);
  std::vector<char> conflict(static_cast<size_t>(na) * nb, 0);
  for (int i = 0; i < na; ++i) {
    for (int j = 0; j < nb; ++j) conflict[i * nb + j] = Meet(a, fa + i, b, fb + j) ? 1 : 0;
  }
  std::vector<Block> blocks;
  std::vector<char> seen(conflict.size(), 0);
  std::vector<int> members;
  for (int start = 0; start < na * nb; ++start) {
    if (!conflict[start] || seen[start]) continue;
    Block block{na, -1, nb, -1, {}, {}};
    std::vector<int> stack{start};
    members.clear();
    seen[start] = 1;
    while (!stack.empty()) {
      const int cell = stack.back();
      stack.pop_back();
      members.push_back(cell);
      const int i = cell / nb;
      const int j = cell % nb;
      block.k1 = std::min(block.k1, i);
      block.k2 = std::max(block.k2, i);
      block.l1 = std::min(block.l1, j);
      block.l2 = std::max(block.l2, j);
      const int neighbours[4][2] = {{i - 1, j}, {i + 1, j}, {i, j - 1}, {i, j + 1}};
      for (const auto& [ni, nj] : neighbours) {
        if (ni < 0 || nj < 0 || ni >= na || nj >= nb) continue;
        const int next = ni * nb + nj;
        if (conflict[next] && !seen[next]) {
          seen[next] = 1;
          stack.push_back(next);
        }
      }
    }
    block.last_k_meeting_l.assign(block.l2 - block.l1 + 1, -1);
    block.last_l_meeting_k.assign(block.k2 - block.k1 + 1, -1);
    for (const int cell : members) {
      const int i = cell / nb;
      const int j = cell % nb;
      int& k_for_l = block.last_k_meeting_l[j - block.l1];
      int& l_for_k = block.last_l_meeting_k[i - block.k1];
      k_for_l = std::max(k_for_l, i + fa);
      l_for_k = std::max(l_for_k, j + fb);
    }
    blocks.push_back({block.k1 + fa, block.k2 + fa, block.l1 + fb, block.l2 + fb,
                      std::move(block.last_k_meeting_l), std::move(block.last_l_meeting_k)});
  }
  return blocks;
}

/// The second robot through a block follows the first: its action `first + n` waits for
/// the first robot's `last_meeting[n]` (once per action that needs more than the one before).
void Follow(Graph& g, int follower, int first, const std::vector<int>& last_meeting, int leader) {
  int needed = -1;
  for (size_t n = 0; n < last_meeting.size(); ++n) {
    if (last_meeting[n] <= needed) continue;
    needed = last_meeting[n];
    g.deps[{follower, first + static_cast<int>(n)}].push_back({leader, needed, -1});
  }
}

/// Follow for the follower's actions from `from` on only (those before it are cleared and
/// wait for nothing more).
void FollowFrom(Graph& g, int follower, int first, const std::vector<int>& last_meeting, int leader,
                int from) {
  for (size_t n = 0; n < last_meeting.size(); ++n) {
    const int action = first + static_cast<int>(n);
    if (action >= from) g.deps[{follower, action}].push_back({leader, last_meeting[n], -1});
  }
}

/// Whether `cells` meets any of the route's action regions first..last.
bool Meets(const CellSet& cells, const ScheduledRoute& route, int first, int last) {
  for (int k = first; k <= last; ++k) {
    if (cells.Intersects(route.action_cells[k])) return true;
  }
  return false;
}

/// The dependency graph, or the route to hold when two routes cannot be ordered at all.
struct BuildResult {
  Graph graph;
  int infeasible_route = -1;
  int infeasible_partner = -1;  ///< the route it cannot be ordered with
};

/// The blocks of routes r and s, computed or remembered.
using BlocksOf = std::function<const std::vector<Block>&(int r, int s)>;

BuildResult Build(const RouteList& routes, const std::vector<bool>& held,
                  const std::vector<ParkedRobot>& parked, const BlocksOf& blocks_of) {
  BuildResult out;
  Graph& g = out.graph;
  // Parked robots and held routes stand where they are.
  std::vector<std::pair<int, const CellSet*>> standing;
  for (size_t p = 0; p < parked.size(); ++p) {
    standing.emplace_back(static_cast<int>(p), &parked[p].cells);
  }
  // So do robots that have finished every action of their routes: they stand at its end
  // until their jobs end.
  std::vector<bool> standing_route(routes.size(), false);
  for (size_t r = 0; r < routes.size(); ++r) {
    const ScheduledRoute& route = routes[r];
    standing_route[r] = held[r] || route.first_unfinished >= Count(route);
    if (!standing_route[r]) continue;
    const int index = static_cast<int>(parked.size() + r);
    standing.emplace_back(index, &Standing(route));
    // A held robot still drives what it was cleared for before it stops: that floor is its
    // too (clearances are never taken back).
    for (int k = std::max(route.first_unfinished, 0); k <= route.cleared_up_to && k < Count(route);
         ++k) {
      standing.emplace_back(index, &route.action_cells[k]);
      standing.emplace_back(index, &route.action_end_cells[k]);
    }
  }
  auto key = [&](int r, int k) {
    const double t = k <= routes[r].cleared_up_to ? -std::numeric_limits<double>::infinity()
                                                  : routes[r].action_start_s[k];
    return std::make_tuple(t, r, k);
  };
  const int n = static_cast<int>(routes.size());
  // Each route's bounds over what is left of it: pairs whose bounds do not meet share no cell,
  // so a large fleet spread over a site costs little more than its routes' lengths.
  std::vector<CellSet> bounds(n);
  for (int r = 0; r < n; ++r) {
    const ScheduledRoute& route = routes[r];
    bounds[r].GrowBounds(route.start_cells);
    for (int k = std::max(0, route.first_unfinished - 1); k < Count(route); ++k) {
      bounds[r].GrowBounds(route.action_cells[k]);
      bounds[r].GrowBounds(route.action_end_cells[k]);
    }
  }
  for (int r = 0; r < n; ++r) {
    if (standing_route[r]) continue;
    const ScheduledRoute& a = routes[r];
    for (const auto& [index, cells] : standing) {
      if (!bounds[r].BoundsOverlap(*cells)) continue;
      for (int k = a.first_unfinished; k < Count(a); ++k) {
        if (!a.action_cells[k].Intersects(*cells)) continue;
        // The whole action waits (from its first segment not yet cleared).
        const int held_from =
            a.whole_from.empty()
                ? k
                : std::max({a.whole_from[k], a.first_unfinished, a.cleared_up_to + 1});
        g.deps[{r, std::min(held_from, k)}].push_back({kParked, -1, index});
      }
    }
    for (int s = r + 1; s < n; ++s) {
      if (standing_route[s] || !bounds[r].BoundsOverlap(bounds[s])) continue;
      const ScheduledRoute& b = routes[s];
      for (const Block& block : blocks_of(r, s)) {
        const bool a_cleared = block.k1 <= a.cleared_up_to;
        const bool b_cleared = block.l1 <= b.cleared_up_to;
        bool a_first;
        if (a_cleared != b_cleared) {
          // The robot already cleared into the block goes on, unless the other stands where
          // it has still to go: then nothing can be ordered, and the other is held.
          const ScheduledRoute& in = a_cleared ? a : b;
          const ScheduledRoute& waiting = a_cleared ? b : a;
          const int in_first = a_cleared ? block.k1 : block.l1;
          const int in_last = a_cleared ? block.k2 : block.l2;
          const int waiting_first = a_cleared ? block.l1 : block.k1;
          if (waiting_first == waiting.first_unfinished &&
              Meets(Standing(waiting), in, std::max(in_first, in.cleared_up_to + 1), in_last)) {
            // Holding the one that stands there can never let the other on (in the dense hall
            // a robot at its pack station stood for good in the way of the next robot to that
            // station, its way out held). Unless its way out passes where the other will stand
            // when done with what it is cleared for, it goes first: it waits only for those of
            // the other's cleared actions that meet its own, and the other follows it through
            // what it is not cleared for yet.
            const int in_route = a_cleared ? r : s;
            const int waiting_route = a_cleared ? s : r;
            const int waiting_last = a_cleared ? block.l2 : block.k2;
            const CellSet& in_stops = in.action_end_cells[in.cleared_up_to];
            if (Meets(in_stops, waiting, waiting_first, waiting_last)) {
              out.infeasible_route = waiting_route;
              out.infeasible_partner = in_route;
              return out;
            }
            FollowFrom(g, in_route, in_first,
                       a_cleared ? block.last_l_meeting_k : block.last_k_meeting_l, waiting_route,
                       in.cleared_up_to + 1);
            for (int l = waiting_first; l <= waiting_last; ++l) {
              for (int k = std::min(in.cleared_up_to, in_last); k >= in_first; --k) {
                if (Meet(in, k, waiting, l)) {
                  g.deps[{waiting_route, l}].push_back({in_route, k, -1});
                  break;
                }
              }
            }
            continue;
          }
          a_first = a_cleared;
        } else {
          // A robot standing in the block cannot make way; one whose route ends in it stays.
          const bool a_stands = block.k1 == a.first_unfinished && !a_cleared &&
                                Meets(Standing(a), b, block.l1, block.l2);
          const bool b_stands = block.l1 == b.first_unfinished && !b_cleared &&
                                Meets(Standing(b), a, block.k1, block.k2);
          const bool a_ends =
              block.k2 == Count(a) - 1 && Meets(a.action_end_cells.back(), b, block.l1, block.l2);
          const bool b_ends =
              block.l2 == Count(b) - 1 && Meets(b.action_end_cells.back(), a, block.k1, block.k2);
          const bool a_must = a_stands || b_ends;
          const bool b_must = b_stands || a_ends;
          if (a_must && b_must && !a_cleared) {
            out.infeasible_route = ToHold(routes, r, s);
            out.infeasible_partner = out.infeasible_route == r ? s : r;
            return out;
          }
          a_first = a_must || (!b_must && key(r, block.k1) < key(s, block.l1));
        }
        if (a_first) {
          Follow(g, s, block.l1, block.last_k_meeting_l, r);
        } else {
          Follow(g, r, block.k1, block.last_l_meeting_k, s);
        }
      }
    }
  }
  return out;
}

/// Of the routes on a cycle, the one to hold: ToHold's pick among those whose robot does not
/// stand in the way of another route on the cycle (held, it would stand there for good: in the
/// dense hall a robot at a pack station, the only one of three not begun, was held again and
/// again while the next robot to that station waited for it), or among all when each does.
int RouteToHoldOf(const RouteList& routes, const std::vector<int>& on_cycle) {
  const auto in_way = [&](int r) {
    return std::any_of(on_cycle.begin(), on_cycle.end(), [&](int s) {
      return s != r && Meets(Standing(routes[r]), routes[s], routes[s].first_unfinished,
                             Count(routes[s]) - 1);
    });
  };
  int hold = -1;
  for (const bool skip_those_in_way : {true, false}) {
    for (int r : on_cycle) {
      if (skip_those_in_way && in_way(r)) continue;
      hold = hold < 0 ? r : ToHold(routes, hold, r);
    }
    if (hold >= 0) return hold;
  }
  return hold;
}

/// A cycle of the graph (intra-route edges k → k+1 plus the dependencies): the route on it to
/// hold (-1: no cycle) and the routes on it.
struct RouteCycle {
  int hold = -1;
  std::vector<int> routes;
};
RouteCycle RouteOnCycle(const RouteList& routes, const std::vector<bool>& held, const Graph& g) {
  // Nodes are numbered route by route: node offset[r] + k is action k of route r.
  const int n = static_cast<int>(routes.size());
  std::vector<int> offset(n + 1, 0);
  for (int r = 0; r < n; ++r) offset[r + 1] = offset[r] + Count(routes[r]);
  std::vector<int> route_of(offset[n]);
  for (int r = 0; r < n; ++r)
    std::fill(route_of.begin() + offset[r], route_of.begin() + offset[r + 1], r);
  // Successors across routes: blocker → waiter (k → k+1 is implicit).
  std::vector<std::vector<int>> next(offset[n]);
  for (const auto& [waiter, deps] : g.deps) {
    for (const Dependency& d : deps) {
      if (d.blocker_route != kParked) {
        next[offset[d.blocker_route] + d.blocker_action].push_back(offset[waiter.first] +
                                                                   waiter.second);
      }
    }
  }
  std::vector<char> color(offset[n], 0);  // 0 new, 1 on stack, 2 done
  // Each frame: the node and how many of its successors have been followed (the last one is
  // the next action of the same route).
  std::vector<std::pair<int, size_t>> stack;
  for (int r = 0; r < n; ++r) {
    if (held[r]) continue;
    for (int k = routes[r].first_unfinished; k < Count(routes[r]); ++k) {
      if (color[offset[r] + k] != 0) continue;
      stack.assign(1, {offset[r] + k, 0});
      color[offset[r] + k] = 1;
      while (!stack.empty()) {
        auto& [node, child] = stack.back();
        const bool has_next_action = node + 1 < offset[route_of[node] + 1];
        const size_t successors = next[node].size() + (has_next_action ? 1 : 0);
        if (child >= successors) {
          color[node] = 2;
          stack.pop_back();
          continue;
        }
        const int to = child < next[node].size() ? next[node][child] : node + 1;
        ++child;
        if (color[to] == 1) {
          // The cycle runs from `to` up the stack: hold the route RouteToHoldOf picks of it.
          RouteCycle cycle{-1, {route_of[to]}};
          for (auto it = stack.rbegin(); it != stack.rend() && it->first != to; ++it) {
            cycle.routes.push_back(route_of[it->first]);
          }
          cycle.hold = RouteToHoldOf(routes, cycle.routes);
          return cycle;
        }
        if (color[to] == 0) {
          color[to] = 1;
          stack.push_back({to, 0});
        }
      }
    }
  }
  return {};
}

/// DecideClearances over the graph that `blocks_of` yields.
std::vector<TrafficClearanceDecision> Decide(const RouteList& routes,
                                             const std::vector<ParkedRobot>& parked,
                                             const BlocksOf& blocks_of) {
  std::vector<bool> held(routes.size(), false);
  // For each held route, the routes it could not be ordered with.
  std::vector<std::vector<int>> held_for(routes.size());
  Graph g;
  while (true) {
    BuildResult built = Build(routes, held, parked, blocks_of);
    if (built.infeasible_route >= 0) {
      held[built.infeasible_route] = true;
      held_for[built.infeasible_route].push_back(built.infeasible_partner);
      continue;
    }
    g = std::move(built.graph);
    const RouteCycle cycle = RouteOnCycle(routes, held, g);
    if (cycle.hold < 0) break;
    held[cycle.hold] = true;
    held_for[cycle.hold] = cycle.routes;
  }
  std::vector<TrafficClearanceDecision> out;
  for (int r = 0; r < static_cast<int>(routes.size()); ++r) {
    const ScheduledRoute& route = routes[r];
    TrafficClearanceDecision decision{route.robot_id,
                                      route.job_id,
                                      std::max(route.cleared_up_to, route.first_unfinished - 1),
                                      {},
                                      static_cast<bool>(held[r])};
    if (held[r]) {
      // It waits for the routes it could not be ordered with (for every route when those are
      // held too): their last actions.
      std::vector<int> partners;
      for (int s : held_for[r]) {
        if (s != r && !held[s] &&
            std::find(partners.begin(), partners.end(), s) == partners.end()) {
          partners.push_back(s);
        }
      }
      for (int s = 0; partners.empty() && s < static_cast<int>(routes.size()); ++s) {
        if (s != r && !held[s]) partners.push_back(s);
      }
      for (int s : partners) {
        decision.waits.push_back(
            {route.robot_id, decision.cleared_up_to + 1, routes[s].robot_id, Count(routes[s]) - 1});
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
            decision.waits.push_back({route.robot_id, k,
                                      parked_robot
                                          ? parked[d.parked_index].robot_id
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

}  // namespace

std::vector<TrafficClearanceDecision> DecideClearances(const std::vector<ScheduledRoute>& routes,
                                                       const std::vector<ParkedRobot>& parked) {
  std::vector<const ScheduledRoute*> pointers;
  pointers.reserve(routes.size());
  for (const ScheduledRoute& route : routes) pointers.push_back(&route);
  return DecideClearances(pointers, parked);
}

std::vector<TrafficClearanceDecision> DecideClearances(
    const std::vector<const ScheduledRoute*>& route_pointers,
    const std::vector<ParkedRobot>& parked) {
  const RouteList routes(route_pointers);
  std::map<std::pair<int, int>, std::vector<Block>> computed;
  return Decide(routes, parked, [&](int r, int s) -> const std::vector<Block>& {
    auto [it, inserted] = computed.try_emplace({r, s});
    if (inserted) it->second = Blocks(routes[r], routes[s]);
    return it->second;
  });
}

std::vector<TrafficClearanceDecision> ClearanceDecider::Decide(
    const std::vector<const ScheduledRoute*>& route_pointers,
    const std::vector<ParkedRobot>& parked) {
  const RouteList routes(route_pointers);
  const uint64_t call = ++calls_;
  std::map<std::pair<int, int>, std::vector<Block>> uncached;
  std::vector<TrafficClearanceDecision> out =
      planner::Decide(routes, parked, [&](int r, int s) -> const std::vector<Block>& {
        const ScheduledRoute& a = routes[r];
        const ScheduledRoute& b = routes[s];
        if (a.cells_id == 0 || b.cells_id == 0) {
          auto [it, inserted] = uncached.try_emplace({r, s});
          if (inserted) it->second = Blocks(a, b);
          return it->second;
        }
        auto [it, inserted] = pairs_.try_emplace({a.cells_id, b.cells_id});
        Remembered& remembered = it->second;
        if (inserted || remembered.first_a != a.first_unfinished ||
            remembered.first_b != b.first_unfinished) {
          remembered.first_a = a.first_unfinished;
          remembered.first_b = b.first_unfinished;
          remembered.blocks = Blocks(a, b);
        }
        remembered.last_call = call;
        return remembered.blocks;
      });
  absl::erase_if(pairs_, [call](const auto& entry) { return entry.second.last_call != call; });
  return out;
}

}  // namespace fleetnav::planner
