#include "fleetnav/planner/mapf/lns.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "absl/container/flat_hash_map.h"
#include "absl/strings/str_cat.h"

namespace fleetnav::planner {
namespace {

constexpr double kWeightReaction = 0.1;  // ALNS: share of the newest improvement in a weight
constexpr double kMinWeight = 0.01;
constexpr int64_t kSippExpansionCap = 200'000;

int At(const std::vector<int>& path, int step) {
  return step < static_cast<int>(path.size()) ? path[step] : path.back();
}

}  // namespace

absl::Status LnsParams::Validate() const {
  if (!(time_limit_s > 0.0) || !std::isfinite(time_limit_s)) {
    return absl::InvalidArgumentError("time_limit_s: must be finite and > 0");
  }
  if (neighborhood_size < 2) return absl::InvalidArgumentError("neighborhood_size: must be >= 2");
  return absl::OkStatus();
}

LnsRefiner::LnsRefiner(const MapfInstance& instance, const LnsParams& params)
    : instance_(instance),
      params_(params),
      rng_(params.seed),
      table_(instance.graph ? instance.graph->size() : 0),
      sipp_(*instance.graph) {}

LnsRefiner::~LnsRefiner() = default;

absl::Status LnsRefiner::Load(const MapfSolution& initial, std::vector<int> fixed_steps) {
  if (absl::Status s = params_.Validate(); !s.ok()) return s;
  if (absl::Status s = ValidateSolution(instance_, initial); !s.ok()) return s;
  const int n = instance_.num_agents();
  if (fixed_steps.empty()) fixed_steps.assign(n, 1);
  if (static_cast<int>(fixed_steps.size()) != n) {
    return absl::InvalidArgumentError(
        absl::StrCat("fixed_steps: ", fixed_steps.size(), " entries for ", n, " agents"));
  }
  paths_ = initial.paths;
  for (int i = 0; i < n; ++i) {
    std::vector<int>& p = paths_[i];
    if (fixed_steps[i] < 1 || fixed_steps[i] > static_cast<int>(p.size())) {
      return absl::InvalidArgumentError(
          absl::StrCat("fixed_steps[", i, "]: ", fixed_steps[i], " is outside 1..", p.size()));
    }
    // Drop the trailing waits at the goal: the table parks the last vertex anyway.
    const size_t keep = std::max<size_t>(PathCost(p, instance_.goals[i]) + 1, fixed_steps[i]);
    p.resize(std::min(p.size(), keep));
  }
  fixed_steps_ = std::move(fixed_steps);
  table_.Clear();
  distances_.resize(n);
  visitors_.assign(instance_.graph->size(), {});
  mark_.assign(n, 0);
  tabu_.assign(n, false);
  shortest_.resize(n);
  for (int i = 0; i < n; ++i) {
    shortest_[i] = fixed_steps_[i] - 1 + Distances(i).Get(paths_[i][fixed_steps_[i] - 1]);
  }
  for (int i = 0; i < n; ++i) {
    const int fixed = fixed_steps_[i];
    if (fixed > 1) {
      const std::vector<int> prefix(paths_[i].begin(), paths_[i].begin() + (fixed - 1));
      table_.AddHardPath(prefix, 0, /*park=*/false);
      // The last committed move belongs to neither the prefix above nor the tail: block the
      // opposite move at its step here, or a replanned robot could swap with it.
      const int before = paths_[i][fixed - 2], last = paths_[i][fixed - 1];
      if (before != last) table_.AddHardEdge(last, before, fixed - 1);
    }
    AddToTable(i);
    IndexVisitors(i, /*add=*/true);
  }
  return absl::OkStatus();
}

DistanceTable& LnsRefiner::Distances(int agent) {
  if (!distances_[agent]) {
    distances_[agent] = std::make_unique<DistanceTable>(*instance_.graph, instance_.goals[agent]);
  }
  return *distances_[agent];
}

int64_t LnsRefiner::Cost(int agent) const {
  return PathCost(paths_[agent], instance_.goals[agent]);
}

// The table holds every committed prefix but its last entry for good (see Load); these two add
// and remove the replannable rest of a path, from its last committed entry on.
std::vector<int> LnsRefiner::Tail(int agent) const {
  return std::vector<int>(paths_[agent].begin() + (fixed_steps_[agent] - 1), paths_[agent].end());
}

void LnsRefiner::AddToTable(int agent) {
  table_.AddHardPath(Tail(agent), fixed_steps_[agent] - 1, /*park=*/true);
}

void LnsRefiner::RemoveFromTable(int agent) {
  table_.RemoveHardPath(Tail(agent), fixed_steps_[agent] - 1, /*park=*/true);
}

void LnsRefiner::IndexVisitors(int agent, bool add) {
  int previous = -1;
  for (int v : paths_[agent]) {
    if (v == previous) continue;
    previous = v;
    std::vector<int>& list = visitors_[v];
    if (add) {
      list.push_back(agent);
    } else {
      list.erase(std::remove(list.begin(), list.end(), agent), list.end());
    }
  }
}

bool LnsRefiner::Replan(const std::vector<int>& agents, bool no_following,
                        std::vector<std::vector<int>>* old_paths) {
  old_paths->clear();
  for (int a : agents) {
    old_paths->push_back(paths_[a]);
    RemoveFromTable(a);
  }
  for (size_t k = 0; k < agents.size(); ++k) {
    const int a = agents[k];
    const int fixed = fixed_steps_[a];
    SippRequest request;
    request.start = paths_[a][fixed - 1];
    request.goal = instance_.goals[a];
    request.start_step = fixed - 1;
    request.max_expansions = kSippExpansionCap;
    request.no_following = no_following;
    // Past the deadline the iteration is abandoned between two robots, so a run overshoots its
    // budget by at most one search.
    const bool late = std::chrono::steady_clock::now() > deadline_;
    absl::StatusOr<SippResult> r = late ? absl::DeadlineExceededError("lns: budget spent")
                                        : sipp_.Plan(request, table_, Distances(a));
    if (!r.ok()) {
      for (size_t j = 0; j < k; ++j) RemoveFromTable(agents[j]);
      for (size_t j = 0; j < agents.size(); ++j) {
        paths_[agents[j]] = (*old_paths)[j];
        AddToTable(agents[j]);
      }
      return false;
    }
    std::vector<int> path(paths_[a].begin(), paths_[a].begin() + (fixed - 1));
    path.insert(path.end(), r->path.begin(), r->path.end());
    paths_[a] = std::move(path);
    AddToTable(a);
  }
  return true;
}

void LnsRefiner::Restore(const std::vector<int>& agents, std::vector<std::vector<int>>& old_paths) {
  for (size_t j = 0; j < agents.size(); ++j) {
    RemoveFromTable(agents[j]);
    paths_[agents[j]] = std::move(old_paths[j]);
    AddToTable(agents[j]);
  }
}

std::vector<int> LnsRefiner::RandomNeighborhood() {
  const int n = instance_.num_agents();
  std::vector<int> out;
  ++mark_stamp_;
  std::uniform_int_distribution<int> pick(0, n - 1);
  for (int tries = 0; tries < 4 * params_.neighborhood_size &&
                      static_cast<int>(out.size()) < std::min(n, params_.neighborhood_size);
       ++tries) {
    const int a = pick(rng_);
    if (mark_[a] == mark_stamp_) continue;
    mark_[a] = mark_stamp_;
    out.push_back(a);
  }
  return out;
}

std::vector<int> LnsRefiner::AgentBasedNeighborhood() {
  const int n = instance_.num_agents();
  auto delay = [&](int a) { return Cost(a) - shortest_[a]; };
  int chosen = -1;
  int64_t worst = 0;
  for (int pass = 0; pass < 2 && chosen < 0; ++pass) {
    for (int a = 0; a < n; ++a) {
      if (tabu_[a]) continue;
      const int64_t d = delay(a);
      if (d > worst) {
        worst = d;
        chosen = a;
      }
    }
    if (chosen < 0) tabu_.assign(n, false);  // everyone had a turn: start over
  }
  if (chosen < 0) return RandomNeighborhood();
  tabu_[chosen] = true;
  ++mark_stamp_;
  std::vector<int> out = {chosen};
  mark_[chosen] = mark_stamp_;
  // Walk a random shortest path of the chosen agent, ignoring the others; whoever stands on
  // it at that step is in the way.
  const GridGraph& g = *instance_.graph;
  DistanceTable& dist = Distances(chosen);
  int step = fixed_steps_[chosen] - 1;
  int v = paths_[chosen][step];
  while (static_cast<int>(out.size()) < params_.neighborhood_size) {
    for (int other : visitors_[v]) {
      if (mark_[other] == mark_stamp_ || At(paths_[other], step) != v) continue;
      mark_[other] = mark_stamp_;
      out.push_back(other);
    }
    if (v == instance_.goals[chosen]) break;
    int options[4];
    int count = 0;
    for (int k = 0; k < g.Degree(v); ++k) {
      const int u = g.Neighbor(v, k);
      if (dist.Get(u) == dist.Get(v) - 1) options[count++] = u;
    }
    if (count == 0) break;
    v = options[std::uniform_int_distribution<int>(0, count - 1)(rng_)];
    ++step;
  }
  // Fill up with agents that pass through the chosen agent's current path.
  const std::vector<int>& path = paths_[chosen];
  std::uniform_int_distribution<size_t> pick(0, path.size() - 1);
  for (int tries = 0; tries < 8 && static_cast<int>(out.size()) < params_.neighborhood_size;
       ++tries) {
    for (int other : visitors_[path[pick(rng_)]]) {
      if (mark_[other] == mark_stamp_ || static_cast<int>(out.size()) >= params_.neighborhood_size)
        continue;
      mark_[other] = mark_stamp_;
      out.push_back(other);
    }
  }
  return out;
}

std::vector<int> LnsRefiner::IntersectionNeighborhood() {
  const GridGraph& g = *instance_.graph;
  const int n = instance_.num_agents();
  // A random junction on a random agent's path, then outwards breadth-first.
  const std::vector<int>& path = paths_[std::uniform_int_distribution<int>(0, n - 1)(rng_)];
  int start = path[std::uniform_int_distribution<size_t>(0, path.size() - 1)(rng_)];
  for (int tries = 0; tries < 16 && g.Degree(start) < 3; ++tries) {
    start = path[std::uniform_int_distribution<size_t>(0, path.size() - 1)(rng_)];
  }
  ++mark_stamp_;
  std::vector<int> out;
  absl::flat_hash_map<int, bool> seen = {{start, true}};
  std::vector<int> queue = {start};
  for (size_t head = 0;
       head < queue.size() && head < 64 && static_cast<int>(out.size()) < params_.neighborhood_size;
       ++head) {
    const int v = queue[head];
    std::vector<int> here = visitors_[v];
    std::shuffle(here.begin(), here.end(), rng_);
    for (int a : here) {
      if (mark_[a] == mark_stamp_ || static_cast<int>(out.size()) >= params_.neighborhood_size)
        continue;
      mark_[a] = mark_stamp_;
      out.push_back(a);
    }
    for (int k = 0; k < g.Degree(v); ++k) {
      const int u = g.Neighbor(v, k);
      if (seen.emplace(u, true).second) queue.push_back(u);
    }
  }
  return out;
}

absl::StatusOr<MapfSolution> LnsRefiner::Refine(const MapfSolution& initial, std::stop_token stop,
                                                std::vector<int> fixed_steps, LnsStats* stats,
                                                const ImprovementObserver& on_improved) {
  if (absl::Status s = Load(initial, std::move(fixed_steps)); !s.ok()) return s;
  using Clock = std::chrono::steady_clock;
  const Clock::time_point t0 = Clock::now();
  deadline_ = t0 + std::chrono::duration_cast<Clock::duration>(
                       std::chrono::duration<double>(params_.time_limit_s));
  auto spent_s = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  LnsStats local;
  LnsStats& st = stats ? *stats : local;
  st = {};
  const int n = instance_.num_agents();
  int64_t lower_bound = 0;
  for (int i = 0; i < n; ++i) {
    st.initial_soc += Cost(i);
    lower_bound += shortest_[i];
  }
  int64_t soc = st.initial_soc;
  double weights[3] = {1.0, 1.0, 1.0};
  std::vector<std::vector<int>> old_paths;
  // Nothing to gain once every agent takes its shortest path.
  while (soc > lower_bound && spent_s() < params_.time_limit_s && !stop.stop_requested()) {
    ++st.iterations;
    const int heuristic =
        std::discrete_distribution<int>({weights[0], weights[1], weights[2]})(rng_);
    std::vector<int> agents = heuristic == 0   ? AgentBasedNeighborhood()
                              : heuristic == 1 ? IntersectionNeighborhood()
                                               : RandomNeighborhood();
    if (agents.empty()) continue;
    std::shuffle(agents.begin(), agents.end(), rng_);
    int64_t old_cost = 0;
    for (int a : agents) {
      old_cost += Cost(a);
      IndexVisitors(a, /*add=*/false);
    }
    double gain = 0.0;
    if (Replan(agents, params_.forbid_following, &old_paths)) {
      int64_t new_cost = 0;
      for (int a : agents) new_cost += Cost(a);
      if (new_cost < old_cost) {
        gain = static_cast<double>(old_cost - new_cost);
        soc -= old_cost - new_cost;
        ++st.accepted;
        st.last_improvement_ms = spent_s() * 1000.0;
        if (on_improved) on_improved(MapfSolution{paths_}, st.last_improvement_ms);
      } else {
        Restore(agents, old_paths);
      }
    }
    for (int a : agents) IndexVisitors(a, /*add=*/true);
    weights[heuristic] =
        std::max(kMinWeight, (1.0 - kWeightReaction) * weights[heuristic] + kWeightReaction * gain);
  }
  st.final_soc = soc;
  return MapfSolution{paths_};
}

absl::StatusOr<MapfSolution> LnsRefiner::RemoveRotations(const MapfSolution& initial,
                                                         std::stop_token stop,
                                                         std::vector<int> fixed_steps) {
  if (absl::Status s = Load(initial, std::move(fixed_steps)); !s.ok()) return s;
  using Clock = std::chrono::steady_clock;
  const Clock::time_point t0 = Clock::now();
  deadline_ = Clock::time_point::max();
  std::vector<std::vector<int>> old_paths;
  int failures = 0;
  int rotations = CountRotations(MapfSolution{paths_});
  for (int attempt = 0;; ++attempt) {
    int step = 0;
    std::vector<int> agents = FindRotation(MapfSolution{paths_}, &step);
    if (agents.empty()) return MapfSolution{paths_};
    if (std::all_of(agents.begin(), agents.end(), [&](int a) { return fixed_steps_[a] > step; })) {
      return absl::FailedPreconditionError(
          absl::StrCat("rotation at step ", step, " lies inside the committed prefixes"));
    }
    if (stop.stop_requested()) return absl::CancelledError("rotation removal stopped");
    if (std::chrono::duration<double>(Clock::now() - t0).count() > params_.time_limit_s) {
      return absl::DeadlineExceededError(absl::StrCat(
          "rotation of ", agents.size(), " robots at step ", step, " left after the budget"));
    }
    // After failures widen the neighbourhood, two robots per failure: first robots whose paths
    // cross the rotating ones' paths (a robot parked on the only way to a goal, one hemming a
    // start in), then random ones.
    if (failures > 0) {
      const size_t target = agents.size() + 2 * static_cast<size_t>(failures);
      ++mark_stamp_;
      for (int a : agents) mark_[a] = mark_stamp_;
      std::vector<int> nearby;
      for (int a : agents) {
        for (int v : paths_[a]) {
          for (int other : visitors_[v]) {
            if (mark_[other] != mark_stamp_) {
              mark_[other] = mark_stamp_;
              nearby.push_back(other);
            }
          }
        }
      }
      std::shuffle(nearby.begin(), nearby.end(), rng_);
      for (int a : nearby) {
        if (agents.size() >= target) break;
        agents.push_back(a);
      }
      for (int a : RandomNeighborhood()) {
        if (agents.size() >= target) break;
        if (std::find(agents.begin(), agents.end(), a) == agents.end()) agents.push_back(a);
      }
    }
    // Two ways, alternated: replan with following forbidden (then no rotation can contain the
    // replanned robots), or replan freely and keep the result only if rotations became fewer;
    // the first fails where robots are packed tight, the second where the cheapest paths
    // rotate again.
    const bool no_following = attempt % 2 == 0;
    std::shuffle(agents.begin(), agents.end(), rng_);
    for (int a : agents) IndexVisitors(a, /*add=*/false);
    bool kept = Replan(agents, no_following, &old_paths);
    if (kept) {
      const int now = CountRotations(MapfSolution{paths_});
      kept = no_following || now < rotations;
      if (kept) {
        rotations = now;
      } else {
        Restore(agents, old_paths);
      }
    }
    failures = kept ? 0 : failures + 1;
    for (int a : agents) IndexVisitors(a, /*add=*/true);
  }
}

namespace {

// Calls visit(step, cycle) for every rotation in the plan, step by step, until it returns false.
template <typename Visit>
void ForEachRotation(const MapfSolution& solution, Visit visit) {
  const int n = static_cast<int>(solution.paths.size());
  size_t horizon = 0;
  for (const auto& p : solution.paths) horizon = std::max(horizon, p.size());
  absl::flat_hash_map<int, int> holder;  // vertex → agent at the previous step
  std::vector<int> follows(n);
  std::vector<int> colour(n);
  for (int t = 1; t < static_cast<int>(horizon); ++t) {
    holder.clear();
    for (int i = 0; i < n; ++i) holder[At(solution.paths[i], t - 1)] = i;
    // follows[i] = j when i moves into the vertex j leaves in this step.
    for (int i = 0; i < n; ++i) {
      follows[i] = -1;
      const int from = At(solution.paths[i], t - 1), to = At(solution.paths[i], t);
      if (from == to) continue;
      auto it = holder.find(to);
      if (it == holder.end() || it->second == i) continue;
      const int j = it->second;
      if (At(solution.paths[j], t) != to) follows[i] = j;
    }
    std::fill(colour.begin(), colour.end(), 0);
    for (int i = 0; i < n; ++i) {
      int a = i;
      while (a != -1 && colour[a] == 0) {
        colour[a] = i + 1;  // on the walk that started at i
        a = follows[a];
      }
      if (a != -1 && colour[a] == i + 1) {
        std::vector<int> cycle = {a};
        for (int b = follows[a]; b != a; b = follows[b]) cycle.push_back(b);
        if (!visit(t, cycle)) return;
      }
      // Mark the walk as finished so later walks stop on it.
      for (int b = i; b != -1 && colour[b] == i + 1; b = follows[b]) colour[b] = -1;
    }
  }
}

}  // namespace

std::vector<int> FindRotation(const MapfSolution& solution, int* step) {
  std::vector<int> found;
  ForEachRotation(solution, [&](int t, const std::vector<int>& cycle) {
    *step = t;
    found = cycle;
    return false;
  });
  return found;
}

int CountRotations(const MapfSolution& solution) {
  int count = 0;
  ForEachRotation(solution, [&](int, const std::vector<int>&) {
    ++count;
    return true;
  });
  return count;
}

}  // namespace fleetnav::planner
