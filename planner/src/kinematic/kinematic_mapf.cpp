#include "fleetnav/planner/kinematic/kinematic_mapf.hpp"

#include <algorithm>
#include <chrono>
#include <functional>
#include <queue>
#include <random>
#include <tuple>

#include "absl/container/flat_hash_map.h"
#include "absl/container/flat_hash_set.h"
#include "absl/strings/str_cat.h"

namespace fleetnav::planner {
namespace {

constexpr int kDx[4] = {1, 0, -1, 0};
constexpr int kDy[4] = {0, 1, 0, -1};
constexpr int kUnreachable = 1 << 29;
constexpr int kCbsMaxRobots = 12;  // above this prioritized planning goes first

// A robot's states are numbered (y * width + x) * 4 + heading.
struct Motion {
  int to_state;
};

// Everything about one robot that does not depend on the others: which states its footprint
// fits in, the cells each state covers, its moves, and the exact static distance to its goal.
class RobotSpace {
 public:
  RobotSpace(const MovingAiMap& map, const GridRobot& robot) : map_(map), robot_(robot) {}

  int StateOf(const GridState& s) const { return ((s.y * map_.width) + s.x) * 4 + s.heading; }
  GridState StateAt(int id) const {
    const int cell = id / 4;
    return {cell % map_.width, cell / map_.width, id % 4};
  }

  // Cells (row-major indices) covered in state `id`, or false when off the map or blocked.
  bool Cells(int id, std::vector<int>* out) const {
    return CoveredCells(map_, robot_.motion, StateAt(id), out);
  }
  bool Fits(int id) const {
    if (!fits_.empty()) return fits_[id] != 0;
    std::vector<int> cells;
    return Cells(id, &cells);
  }

  bool MoveAllowed(const GridState& from, int direction) const {
    const auto& lanes = robot_.motion.allowed_moves;
    return lanes.empty() || (lanes[from.y * map_.width + from.x] >> direction) & 1;
  }

  // Successor states of `id` (waits excluded), each fitting the map.
  void Successors(int id, std::vector<int>* out) const {
    out->clear();
    const GridState s = StateAt(id);
    auto add_move = [&](int direction, int heading) {
      if (!MoveAllowed(s, direction)) return;
      const GridState n{s.x + kDx[direction], s.y + kDy[direction], heading};
      if (!map_.Passable(n.x, n.y)) return;
      const int nid = StateOf(n);
      if (Fits(nid)) out->push_back(nid);
    };
    if (!robot_.motion.has_heading) {
      for (int d = 0; d < 4; ++d) add_move(d, kPlusX);
      return;
    }
    add_move(s.heading, s.heading);
    if (robot_.motion.may_reverse) add_move((s.heading + 2) % 4, s.heading);
    for (int turn : {1, 3}) {
      const int nid = StateOf({s.x, s.y, (s.heading + turn) % 4});
      if (Fits(nid)) out->push_back(nid);
    }
  }

  bool IsGoal(int id) const {
    const GridState s = StateAt(id);
    return s.x == robot_.goal_x && s.y == robot_.goal_y &&
           (robot_.goal_heading < 0 || robot_.goal_heading == s.heading);
  }

  // Exact distance (in steps) to the goal from every state, by a backward search: the
  // predecessors of a state are found by trying every state's successors once, inverted.
  void ComputeDistances() {
    const int n = map_.width * map_.height * 4;
    // Which states the footprint fits in, once: the searches ask for every successor.
    std::vector<uint8_t> fits(n);
    std::vector<int> next;
    for (int id = 0; id < n; ++id) fits[id] = Cells(id, &next) ? 1 : 0;
    fits_ = std::move(fits);
    std::vector<std::vector<int>> predecessors(n);
    for (int id = 0; id < n; ++id) {
      if (!Fits(id)) continue;
      Successors(id, &next);
      for (int to : next) predecessors[to].push_back(id);
    }
    distance_.assign(n, kUnreachable);
    std::vector<int> queue;
    for (int id = 0; id < n; ++id) {
      if (IsGoal(id) && Fits(id)) {
        distance_[id] = 0;
        queue.push_back(id);
      }
    }
    for (size_t head = 0; head < queue.size(); ++head) {
      const int v = queue[head];
      for (int u : predecessors[v]) {
        if (distance_[u] == kUnreachable) {
          distance_[u] = distance_[v] + 1;
          queue.push_back(u);
        }
      }
    }
  }
  int Distance(int id) const { return distance_[id]; }

 private:
  const MovingAiMap& map_;
  const GridRobot& robot_;
  std::vector<int> distance_;
  std::vector<uint8_t> fits_;  // per state, once ComputeDistances has run
};

// Reservations per (cell, half step): states at 2t, moves from t to t + 1 at 2t + 1. A parked
// robot holds its cells from a half step on for ever.
class HalfStepReservations {
 public:
  void Reserve(int cell, int half_step) {
    taken_.insert(Key(cell, half_step));
    last_[cell] = std::max(last_[cell], half_step);
  }
  void Park(int cell, int half_step) {
    auto [it, fresh] = parked_.emplace(cell, half_step);
    if (!fresh) it->second = std::min(it->second, half_step);
  }
  void Unpark(int cell) { parked_.erase(cell); }
  bool Free(const std::vector<int>& cells, int half_step) const {
    for (int c : cells) {
      if (taken_.contains(Key(c, half_step))) return false;
      if (auto it = parked_.find(c); it != parked_.end() && it->second <= half_step) return false;
    }
    return true;
  }
  // Whether the cells stay free from `half_step` on for ever.
  bool FreeFrom(const std::vector<int>& cells, int half_step) const {
    for (int c : cells) {
      if (auto it = last_.find(c); it != last_.end() && it->second >= half_step) return false;
      if (parked_.contains(c)) return false;
    }
    return true;
  }
  void Clear() {
    taken_.clear();
    last_.clear();
    parked_.clear();
  }

 private:
  static int64_t Key(int cell, int half_step) {
    return (static_cast<int64_t>(half_step) << 32) | static_cast<uint32_t>(cell);
  }
  absl::flat_hash_set<int64_t> taken_;
  absl::flat_hash_map<int, int> last_;
  absl::flat_hash_map<int, int> parked_;
};

std::vector<int> Union(std::vector<int> a, const std::vector<int>& b) {
  a.insert(a.end(), b.begin(), b.end());
  std::sort(a.begin(), a.end());
  a.erase(std::unique(a.begin(), a.end()), a.end());
  return a;
}

// How many other robots' current paths cover a cell at a half step (a conflict-avoidance
// table): the low level of conflict-based search prefers, among equally short paths, the one
// that meets the others least.
class SoftOccupancy {
 public:
  void AddPath(const RobotSpace& space, const std::vector<int>& states) {
    std::vector<int> here, there;
    for (size_t t = 0; t < states.size(); ++t) {
      space.Cells(states[t], &here);
      for (int c : here) ++count_[Key(c, 2 * static_cast<int>(t))];
      if (t + 1 < states.size()) {
        space.Cells(states[t + 1], &there);
        for (int c : Union(here, there)) ++count_[Key(c, 2 * static_cast<int>(t) + 1)];
      } else {
        for (int c : here) parked_[c] = 2 * static_cast<int>(t);
      }
    }
  }
  int Conflicts(const std::vector<int>& cells, int half_step) const {
    int n = 0;
    for (int c : cells) {
      if (auto it = count_.find(Key(c, half_step)); it != count_.end()) n += it->second;
      if (auto it = parked_.find(c); it != parked_.end() && it->second <= half_step) ++n;
    }
    return n;
  }

 private:
  static int64_t Key(int cell, int half_step) {
    return (static_cast<int64_t>(half_step) << 32) | static_cast<uint32_t>(cell);
  }
  absl::flat_hash_map<int64_t, int> count_;
  absl::flat_hash_map<int, int> parked_;
};

// Space-time A* for one robot against the reservations; the state sequence or empty. With
// `soft`, ties on f go to the path with fewer soft conflicts.
std::vector<int> SearchRobot(const RobotSpace& space, int start, const HalfStepReservations& res,
                             int max_steps, const SoftOccupancy* soft = nullptr) {
  struct Node {
    int state;
    int t;
    int parent;
    int conflicts;
  };
  std::vector<Node> nodes;
  using Entry = std::tuple<int, int, int, int>;  // f, conflicts, −t, node
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> open;
  absl::flat_hash_map<int64_t, int> best;  // (state, t) → fewest conflicts generated
  auto key = [](int state, int t) { return (static_cast<int64_t>(t) << 32) | state; };
  std::vector<int> here, there, next, moving;
  if (space.Distance(start) >= kUnreachable) return {};
  nodes.push_back({start, 0, -1, 0});
  open.push({space.Distance(start), 0, 0, 0});
  best[key(start, 0)] = 0;
  while (!open.empty()) {
    const int id = std::get<3>(open.top());
    open.pop();
    const Node cur = nodes[id];
    if (best[key(cur.state, cur.t)] < cur.conflicts) continue;  // superseded
    space.Cells(cur.state, &here);
    if (space.IsGoal(cur.state) && res.FreeFrom(here, 2 * cur.t)) {
      std::vector<int> states(cur.t + 1);
      for (int k = id; k >= 0; k = nodes[k].parent) states[nodes[k].t] = nodes[k].state;
      return states;
    }
    if (cur.t >= max_steps) continue;
    space.Successors(cur.state, &next);
    next.push_back(cur.state);  // wait
    for (int to : next) {
      const int h = space.Distance(to);
      if (h >= kUnreachable) continue;
      space.Cells(to, &there);
      if (!res.Free(there, 2 * cur.t + 2)) continue;
      moving = to == cur.state ? here : Union(here, there);
      if (!res.Free(moving, 2 * cur.t + 1)) continue;
      const int conflicts = cur.conflicts + (soft ? soft->Conflicts(moving, 2 * cur.t + 1) +
                                                        soft->Conflicts(there, 2 * cur.t + 2)
                                                  : 0);
      auto [it, fresh] = best.try_emplace(key(to, cur.t + 1), conflicts);
      if (!fresh) {
        if (it->second <= conflicts) continue;
        it->second = conflicts;
      }
      nodes.push_back({to, cur.t + 1, id, conflicts});
      open.push({cur.t + 1 + h, conflicts, -(cur.t + 1), static_cast<int>(nodes.size()) - 1});
    }
  }
  return {};
}

// The first overlap of two robots' plans (state ids per step): robots, cell and half step.
struct Overlap {
  int a = -1;
  int b = -1;
  int cell = 0;
  int half_step = 0;
};

Overlap FirstOverlap(const std::vector<RobotSpace>& spaces,
                     const std::vector<std::vector<int>>& paths) {
  size_t horizon = 0;
  for (const auto& p : paths) horizon = std::max(horizon, p.size());
  auto at = [&](size_t i, size_t t) { return t < paths[i].size() ? paths[i][t] : paths[i].back(); };
  absl::flat_hash_map<int, int> owner;
  std::vector<int> a, b;
  for (size_t half = 0; half < 2 * horizon; ++half) {
    owner.clear();
    const size_t t = half / 2;
    for (size_t i = 0; i < paths.size(); ++i) {
      spaces[i].Cells(at(i, t), &a);
      if (half % 2 == 1) {
        spaces[i].Cells(at(i, t + 1), &b);
        a = Union(a, b);
      }
      for (int c : a) {
        auto [it, fresh] = owner.emplace(c, static_cast<int>(i));
        if (!fresh) return {it->second, static_cast<int>(i), c, static_cast<int>(half)};
      }
    }
  }
  return {};
}

// Conflict-based search (Sharon et al., AIJ 2015) over the robots' own state spaces: a node
// forbids robots single (cell, half step) pairs; an overlap of robots a and b on cell c at half
// step h splits into "a not on c at h" and "b not on c at h". Best-first on the sum of arrival
// steps, fewer overlaps first on ties. The budget is work (`max_nodes` high-level nodes), so the
// outcome does not depend on the machine's load; the deadline is only a safety net.
struct CbsOutcome {
  std::vector<std::vector<int>> paths;  ///< empty unless solved
  bool interrupted = false;             ///< the deadline passed or a stop was requested
};
CbsOutcome ConflictBasedSearch(const std::vector<RobotSpace>& spaces,
                               const std::vector<int>& starts, int max_steps, size_t max_nodes,
                               std::chrono::steady_clock::time_point deadline,
                               std::stop_token stop) {
  struct Node {
    std::vector<std::vector<int>> paths;
    std::vector<std::vector<std::pair<int, int>>> constraints;
    int64_t cost = 0;
  };
  const int n = static_cast<int>(spaces.size());
  // The low level avoids the other robots' current paths where that costs nothing.
  auto plan_robot = [&](int i, const std::vector<std::pair<int, int>>& constraints,
                        const std::vector<std::vector<int>>& paths) {
    HalfStepReservations res;
    for (const auto& [cell, half] : constraints) res.Reserve(cell, half);
    SoftOccupancy soft;
    for (size_t j = 0; j < paths.size(); ++j) {
      if (static_cast<int>(j) != i && !paths[j].empty()) soft.AddPath(spaces[j], paths[j]);
    }
    return SearchRobot(spaces[i], starts[i], res, max_steps, &soft);
  };
  std::vector<Node> nodes(1);
  nodes[0].constraints.resize(n);
  for (int i = 0; i < n; ++i) {
    nodes[0].paths.push_back(plan_robot(i, {}, nodes[0].paths));
    if (nodes[0].paths.back().empty()) return {};
    nodes[0].cost += static_cast<int64_t>(nodes[0].paths.back().size()) - 1;
  }
  using Entry = std::pair<int64_t, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> open;
  open.push({nodes[0].cost, 0});
  while (!open.empty() && nodes.size() < max_nodes) {
    if (stop.stop_requested() || std::chrono::steady_clock::now() > deadline) {
      return {{}, true};
    }
    const int id = open.top().second;
    open.pop();
    const Overlap o = FirstOverlap(spaces, nodes[id].paths);
    if (o.a < 0) return {std::move(nodes[id].paths), false};
    for (int robot : {o.a, o.b}) {
      Node child = nodes[id];
      child.constraints[robot].push_back({o.cell, o.half_step});
      std::vector<int> path = plan_robot(robot, child.constraints[robot], child.paths);
      if (path.empty()) continue;
      child.cost +=
          static_cast<int64_t>(path.size()) - static_cast<int64_t>(child.paths[robot].size());
      child.paths[robot] = std::move(path);
      open.push({child.cost, static_cast<int>(nodes.size())});
      nodes.push_back(std::move(child));
    }
  }
  return {};
}

}  // namespace

bool CoveredCells(const MovingAiMap& map, const GridMotionModel& motion, const GridState& s,
                  std::vector<int>* cells) {
  cells->clear();
  for (const auto& [fx, fy] : motion.footprint_cells) {
    int dx = fx, dy = fy;
    for (int k = 0; k < s.heading; ++k) std::tie(dx, dy) = std::make_tuple(-dy, dx);
    const int x = s.x + dx, y = s.y + dy;
    if (!map.Passable(x, y)) return false;
    cells->push_back(y * map.width + x);
  }
  return true;
}

absl::Status KinematicMapfProblem::Validate() const {
  if (map == nullptr) return absl::InvalidArgumentError("map: missing");
  std::vector<std::vector<int>> start_cells(robots.size());
  for (size_t i = 0; i < robots.size(); ++i) {
    const GridRobot& r = robots[i];
    const std::string field = absl::StrCat("robots[", i, "]");
    if (r.start_heading < 0 || r.start_heading > 3 || r.goal_heading < -1 || r.goal_heading > 3) {
      return absl::InvalidArgumentError(absl::StrCat(field, ": heading must be 0..3"));
    }
    if (!r.motion.has_heading && (r.start_heading != kPlusX || r.goal_heading > 0)) {
      return absl::InvalidArgumentError(
          absl::StrCat(field, ": a robot without heading uses heading 0"));
    }
    if (std::find(r.motion.footprint_cells.begin(), r.motion.footprint_cells.end(),
                  std::array<int, 2>{0, 0}) == r.motion.footprint_cells.end()) {
      return absl::InvalidArgumentError(
          absl::StrCat(field, ".motion.footprint_cells: must contain (0, 0)"));
    }
    if (!r.motion.allowed_moves.empty() &&
        r.motion.allowed_moves.size() != static_cast<size_t>(map->width) * map->height) {
      return absl::InvalidArgumentError(
          absl::StrCat(field, ".motion.allowed_moves: one mask per cell of the map"));
    }
    RobotSpace space(*map, r);
    if (!space.Cells(space.StateOf({r.start_x, r.start_y, r.start_heading}), &start_cells[i])) {
      return absl::InvalidArgumentError(absl::StrCat(field, ".start: footprint not on free cells"));
    }
    std::vector<int> goal_cells;
    const bool goal_fits =
        r.goal_heading >= 0
            ? space.Cells(space.StateOf({r.goal_x, r.goal_y, r.goal_heading}), &goal_cells)
            : map->Passable(r.goal_x, r.goal_y);
    if (!goal_fits) {
      return absl::InvalidArgumentError(absl::StrCat(field, ".goal: footprint not on free cells"));
    }
    for (size_t j = 0; j < i; ++j) {
      for (int c : start_cells[i]) {
        if (std::find(start_cells[j].begin(), start_cells[j].end(), c) != start_cells[j].end()) {
          return absl::InvalidArgumentError(
              absl::StrCat(field, ".start: overlaps robots[", j, "] at its start"));
        }
      }
    }
  }
  return absl::OkStatus();
}

absl::Status ValidateKinematicPlan(const KinematicMapfProblem& problem,
                                   const KinematicMapfPlan& plan) {
  if (absl::Status s = problem.Validate(); !s.ok()) return s;
  const size_t n = problem.robots.size();
  if (plan.states.size() != n) {
    return absl::InvalidArgumentError(
        absl::StrCat("plan: ", plan.states.size(), " robots, problem has ", n));
  }
  std::vector<RobotSpace> spaces;
  std::vector<std::vector<int>> ids(n);
  for (size_t i = 0; i < n; ++i) {
    const GridRobot& r = problem.robots[i];
    const auto& states = plan.states[i];
    spaces.emplace_back(*problem.map, r);
    if (states.empty() || !(states.front() == GridState{r.start_x, r.start_y, r.start_heading})) {
      return absl::InvalidArgumentError(absl::StrCat("robot ", i, ": does not start at its start"));
    }
    const GridState& last = states.back();
    if (last.x != r.goal_x || last.y != r.goal_y ||
        (r.goal_heading >= 0 && last.heading != r.goal_heading)) {
      return absl::InvalidArgumentError(absl::StrCat("robot ", i, ": does not end at its goal"));
    }
    std::vector<int> next;
    for (size_t t = 0; t < states.size(); ++t) {
      const int id = spaces[i].StateOf(states[t]);
      ids[i].push_back(id);
      if (states[t].heading < 0 || states[t].heading > 3 || !spaces[i].Fits(id)) {
        return absl::InvalidArgumentError(
            absl::StrCat("robot ", i, " step ", t, ": footprint not on free cells"));
      }
      if (t == 0 || states[t] == states[t - 1]) continue;
      spaces[i].Successors(spaces[i].StateOf(states[t - 1]), &next);
      if (std::find(next.begin(), next.end(), id) == next.end()) {
        return absl::InvalidArgumentError(
            absl::StrCat("robot ", i, " step ", t, ": a move its motion model does not allow"));
      }
    }
  }
  const Overlap o = FirstOverlap(spaces, ids);
  if (o.a >= 0) {
    const int w = problem.map->width;
    return absl::InvalidArgumentError(absl::StrCat(
        "robots ", o.a, " and ", o.b, " overlap at cell (", o.cell % w, ",", o.cell / w, ") ",
        o.half_step % 2 ? "moving from step " : "at step ", o.half_step / 2));
  }
  return absl::OkStatus();
}

absl::StatusOr<KinematicMapfPlan> PlanKinematicMapf(const KinematicMapfProblem& problem,
                                                    const KinematicMapfParams& params,
                                                    std::stop_token stop) {
  if (!(params.time_limit_s > 0.0) || params.max_steps <= 0 || params.cbs_max_nodes < 0 ||
      params.max_priority_orders <= 0) {
    return absl::InvalidArgumentError(
        "params: time_limit_s, max_steps and max_priority_orders must be > 0, cbs_max_nodes >= 0");
  }
  if (absl::Status s = problem.Validate(); !s.ok()) return s;
  using Clock = std::chrono::steady_clock;
  const Clock::time_point t0 = Clock::now();
  const int n = static_cast<int>(problem.robots.size());
  std::vector<RobotSpace> spaces;
  spaces.reserve(n);
  std::vector<int> starts(n);
  std::vector<std::vector<int>> start_cells(n);
  for (int i = 0; i < n; ++i) {
    const GridRobot& r = problem.robots[i];
    spaces.emplace_back(*problem.map, r);
    spaces[i].ComputeDistances();
    starts[i] = spaces[i].StateOf({r.start_x, r.start_y, r.start_heading});
    spaces[i].Cells(starts[i], &start_cells[i]);
    if (spaces[i].Distance(starts[i]) >= kUnreachable) {
      return absl::InvalidArgumentError(
          absl::StrCat("robots[", i, "].goal: unreachable for its motion model"));
    }
  }
  const auto deadline = t0 + std::chrono::duration_cast<Clock::duration>(
                                 std::chrono::duration<double>(params.time_limit_s));
  auto out_of_time = [&](int attempts) -> absl::Status {
    if (stop.stop_requested()) return absl::CancelledError("kinematic mapf: stopped");
    return absl::DeadlineExceededError(absl::StrCat("kinematic mapf: no plan within ",
                                                    params.time_limit_s, " s (", attempts,
                                                    " priority orders tried)"));
  };
  // Few robots: conflict-based search first; it solves the tight puzzles (a swap through a bay)
  // that prioritized planning cannot.
  if (n <= kCbsMaxRobots && params.cbs_max_nodes > 0) {
    CbsOutcome cbs = ConflictBasedSearch(spaces, starts, params.max_steps,
                                         static_cast<size_t>(params.cbs_max_nodes), deadline, stop);
    if (cbs.interrupted) return out_of_time(0);
    if (!cbs.paths.empty()) {
      const std::vector<std::vector<int>>& paths = cbs.paths;
      KinematicMapfPlan plan;
      plan.states.resize(n);
      for (int i = 0; i < n; ++i) {
        for (int id : paths[i]) plan.states[i].push_back(spaces[i].StateAt(id));
      }
      return plan;
    }
  }
  std::vector<int> order(n);
  for (int i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return spaces[a].Distance(starts[a]) > spaces[b].Distance(starts[b]);
  });
  std::mt19937_64 rng(params.seed);
  HalfStepReservations res;
  std::vector<int> here, there;
  for (int attempt = 0;; ++attempt) {
    if (attempt == params.max_priority_orders) {
      const bool ran_cbs = n <= kCbsMaxRobots && params.cbs_max_nodes > 0;
      return absl::ResourceExhaustedError(absl::StrCat(
          "kinematic mapf: no plan in ",
          ran_cbs ? absl::StrCat(params.cbs_max_nodes, " conflict-based search nodes and ") : "",
          attempt, " priority orders"));
    }
    if (stop.stop_requested() || Clock::now() > deadline) return out_of_time(attempt);
    const bool revised = attempt % 2 == 0;  // robots not yet planned block their start cells
    if (attempt > 1) std::shuffle(order.begin(), order.end(), rng);
    res.Clear();
    if (revised) {
      for (int i = 0; i < n; ++i) {
        for (int c : start_cells[i]) res.Park(c, 0);
      }
    } else {
      for (int i = 0; i < n; ++i) {
        for (int c : start_cells[i]) res.Reserve(c, 0);
      }
    }
    KinematicMapfPlan plan;
    plan.states.resize(n);
    bool ok = true;
    for (int i : order) {
      if (revised) {
        for (int c : start_cells[i]) res.Unpark(c);
      }
      const std::vector<int> states = SearchRobot(spaces[i], starts[i], res, params.max_steps);
      if (states.empty()) {
        ok = false;
        break;
      }
      for (size_t t = 0; t < states.size(); ++t) {
        spaces[i].Cells(states[t], &here);
        for (int c : here) res.Reserve(c, 2 * static_cast<int>(t));
        if (t + 1 < states.size()) {
          spaces[i].Cells(states[t + 1], &there);
          for (int c : Union(here, there)) res.Reserve(c, 2 * static_cast<int>(t) + 1);
        } else {
          for (int c : here) res.Park(c, 2 * static_cast<int>(t));
        }
        plan.states[i].push_back(spaces[i].StateAt(states[t]));
      }
    }
    if (ok) return plan;
  }
}

}  // namespace fleetnav::planner
