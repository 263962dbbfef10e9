#include "fleetnav/planner/mapf/lacam.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <queue>

#include "absl/strings/str_cat.h"

namespace fleetnav::planner {
namespace {

constexpr int kNone = -1;

uint64_t HashConfig(const int* q, int n) {
  uint64_t h = 0x9e3779b97f4a7c15ULL ^ static_cast<uint64_t>(n);
  for (int i = 0; i < n; ++i) {
    h ^= static_cast<uint64_t>(q[i]) + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
  }
  return h;
}

}  // namespace

absl::Status LacamParams::Validate() const {
  if (max_stored_agent_states <= 0) {
    return absl::InvalidArgumentError("max_stored_agent_states: must be > 0");
  }
  return absl::OkStatus();
}

bool LacamSolver::NodeEq::operator()(int a, int b) const {
  return s->nodes_[a].hash == s->nodes_[b].hash &&
         std::memcmp(s->Config(a), s->Config(b), sizeof(int) * s->n_) == 0;
}

LacamSolver::LacamSolver(const LacamParams& params)
    : params_(params), explored_(0, NodeHash{this}, NodeEq{this}) {}

int LacamSolver::PushLow(int node, int parent, int who, int where, int depth) {
  const int id = static_cast<int>(low_.size());
  low_.push_back({parent, who, where, depth, kNone});
  HighNode& h = nodes_[node];
  if (h.low_tail == kNone) {
    h.low_head = h.low_tail = id;
  } else {
    low_[h.low_tail].next = id;
    h.low_tail = id;
  }
  return id;
}

int64_t LacamSolver::EdgeCost(int a, int b) const {
  // Sum of loss (LaCAM*): every agent that is not resting at its goal pays one.
  const int* qa = Config(a);
  const int* qb = Config(b);
  int64_t cost = 0;
  for (int i = 0; i < n_; ++i) {
    const int g = instance_.goals[i];
    if (qa[i] != g || qb[i] != g) ++cost;
  }
  return cost;
}

int LacamSolver::InternNode(int parent, bool* is_new) {
  const int id = static_cast<int>(nodes_.size());
  const int64_t offset = static_cast<int64_t>(config_.size());
  config_.insert(config_.end(), next_.begin(), next_.end());
  nodes_.push_back({offset, HashConfig(next_.data(), n_), parent, 0, 0, kNone, kNone, kNone});
  auto [it, inserted] = explored_.insert(id);
  if (!inserted) {
    nodes_.pop_back();
    config_.resize(offset);
    *is_new = false;
    return *it;
  }
  *is_new = true;
  // Heuristic, priorities (PIBT's dynamic priorities) and the agent order.
  int64_t h = 0;
  order_.resize(config_.size());
  priority_.resize(config_.size());
  for (int i = 0; i < n_; ++i) {
    const int v = next_[i];
    h += Dist(i, v);
    float p;
    if (parent == kNone) {
      p = static_cast<float>(Dist(i, v)) / static_cast<float>(instance_.graph->size() + 1);
    } else {
      const float before = priority_[nodes_[parent].offset + i];
      p = v != instance_.goals[i] ? before + 1.0f : before - std::floor(before);
    }
    priority_[offset + i] = p;
    order_[offset + i] = i;
  }
  nodes_[id].h = h;
  const float* pr = &priority_[offset];
  std::sort(order_.begin() + offset, order_.begin() + offset + n_,
            [pr](int a, int b) { return pr[a] > pr[b] || (pr[a] == pr[b] && a < b); });
  PushLow(id, kNone, kNone, kNone, 0);
  return id;
}

void LacamSolver::Shuffle(int* values, int count) {
  // Fisher-Yates on SplitMix64 (Steele et al., OOPSLA 2014): the hot loop shuffles at most five
  // values, where std::shuffle on a Mersenne twister cost a tenth of the search.
  for (int a = count - 1; a > 0; --a) {
    rng_state_ += 0x9e3779b97f4a7c15ULL;
    uint64_t z = rng_state_;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    const int b = static_cast<int>((z >> 32) * static_cast<uint64_t>(a + 1) >> 32);
    std::swap(values[a], values[b]);
  }
}

bool LacamSolver::Pibt(int i, const int* from) {
  const GridGraph& g = *instance_.graph;
  const int v_now = from[i];
  int* c = &candidates_[static_cast<size_t>(i) * 5];
  int k = 0;
  const int deg = g.Degree(v_now);
  for (int e = 0; e < deg; ++e) c[k++] = g.Neighbor(v_now, e);
  c[k++] = v_now;
  // Random tie-breaking, then by distance to goal; among equals prefer a vertex nobody holds.
  Shuffle(c, k);
  int key[5];
  for (int a = 0; a < k; ++a) {
    key[a] = Dist(i, c[a]) * 2 + (occupied_now_[c[a]] != kNone && occupied_now_[c[a]] != i);
  }
  for (int a = 1; a < k; ++a) {
    for (int b = a; b > 0 && key[b] < key[b - 1]; --b) {
      std::swap(key[b], key[b - 1]);
      std::swap(c[b], c[b - 1]);
    }
  }
  // The swap technique: when i and the robot ahead can only get past each other by one of
  // them backing out of a corridor, i backs off first and pulls that robot after it.
  const int partner = SwapPartner(i, from, c[0]);
  if (partner != kNone) std::reverse(c, c + k);
  for (int a = 0; a < k; ++a) {
    const int u = c[a];
    if (occupied_next_[u] != kNone) continue;
    const int j = occupied_now_[u];
    if (j != kNone && j != i && next_[j] == v_now) continue;  // swap
    occupied_next_[u] = i;
    next_[i] = u;
    if (j != kNone && j != i && next_[j] == kNone && !Pibt(j, from)) continue;
    if (a == 0 && partner != kNone && next_[partner] == kNone && occupied_next_[v_now] == kNone) {
      occupied_next_[v_now] = partner;
      next_[partner] = v_now;
    }
    return true;
  }
  occupied_next_[v_now] = i;
  next_[i] = v_now;
  return false;
}

bool LacamSolver::RestingInDeadEnd(int u) const {
  const GridGraph& g = *instance_.graph;
  if (g.Degree(u) != 1) return false;
  const int a = occupied_now_[u];
  return a != kNone && instance_.goals[a] == u;
}

int LacamSolver::CorridorStep(int from_v, int v, int* next) const {
  const GridGraph& g = *instance_.graph;
  int open = 0;
  for (int e = 0; e < g.Degree(v); ++e) {
    const int u = g.Neighbor(v, e);
    if (u == from_v || RestingInDeadEnd(u)) continue;
    ++open;
    *next = u;
  }
  return open;
}

bool LacamSolver::SwapRequired(int pusher, int puller, int v_pusher, int v_puller) {
  // Walk the pusher forward, the puller backing out ahead of it, while the pusher gains: if
  // the puller reaches a junction it can step aside and no swap is needed.
  const int limit = instance_.graph->size();
  for (int steps = 0; steps < limit && Dist(pusher, v_puller) < Dist(pusher, v_pusher); ++steps) {
    int ahead = kNone;
    const int open = CorridorStep(v_pusher, v_puller, &ahead);
    if (open >= 2) return false;
    if (open == 0) break;
    v_pusher = v_puller;
    v_puller = ahead;
  }
  return Dist(puller, v_pusher) < Dist(puller, v_puller) &&
         (Dist(pusher, v_pusher) == 0 || Dist(pusher, v_puller) < Dist(pusher, v_pusher));
}

bool LacamSolver::SwapPossible(int v_pusher_origin, int v_puller_origin) const {
  // Pull along the corridor until a junction (room to swap), a dead end or back at the start.
  int v_pusher = v_pusher_origin, v_puller = v_puller_origin;
  const int limit = instance_.graph->size();
  for (int steps = 0; steps < limit && v_puller != v_pusher_origin; ++steps) {
    int ahead = kNone;
    const int open = CorridorStep(v_pusher, v_puller, &ahead);
    if (open >= 2) return true;
    if (open == 0) return false;
    v_pusher = v_puller;
    v_puller = ahead;
  }
  return false;
}

int LacamSolver::SwapPartner(int i, const int* from, int target) {
  const int j = occupied_now_[target];
  if (j != kNone && j != i && next_[j] == kNone && SwapRequired(i, j, from[i], from[j]) &&
      SwapPossible(from[j], from[i])) {
    return j;
  }
  // The clear operation of push and swap: a neighbour that i's step would have to pass.
  if (target != from[i]) {
    const GridGraph& g = *instance_.graph;
    for (int e = 0; e < g.Degree(from[i]); ++e) {
      const int k = occupied_now_[g.Neighbor(from[i], e)];
      if (k != kNone && from[k] != target && SwapRequired(k, i, from[i], target) &&
          SwapPossible(target, from[i])) {
        return k;
      }
    }
  }
  return kNone;
}

bool LacamSolver::Generate(int node, int low) {
  const int* from = Config(node);
  const int* order = &order_[nodes_[node].offset];
  for (int i = 0; i < n_; ++i) {
    next_[i] = kNone;
    occupied_now_[from[i]] = i;
  }
  bool ok = true;
  for (int c = low; c != kNone && low_[c].who != kNone; c = low_[c].parent) {
    const int who = low_[c].who;
    const int where = low_[c].where;
    if (occupied_next_[where] != kNone) {
      ok = false;
      break;
    }
    const int j = occupied_now_[where];
    if (j != kNone && j != who && next_[j] == from[who]) {
      ok = false;
      break;
    }
    next_[who] = where;
    occupied_next_[where] = who;
  }
  if (ok) {
    for (int k = 0; k < n_; ++k) {
      const int i = order[k];
      if (next_[i] == kNone && !Pibt(i, from)) {
        ok = false;
        break;
      }
    }
  }
  for (int i = 0; i < n_; ++i) {
    occupied_now_[from[i]] = kNone;
    if (next_[i] != kNone) occupied_next_[next_[i]] = kNone;
  }
  return ok;
}

void LacamSolver::AddEdge(int from, int to) {
  for (int e = nodes_[from].edge_head; e != kNone; e = edges_[e].next) {
    if (edges_[e].to == to) return;
  }
  edges_.push_back({to, EdgeCost(from, to), nodes_[from].edge_head});
  nodes_[from].edge_head = static_cast<int>(edges_.size()) - 1;
}

void LacamSolver::Rewire(int from) {
  // Dijkstra from `from` over the explored graph: lower every reachable g and re-parent.
  using Item = std::pair<int64_t, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  open.push({nodes_[from].g, from});
  while (!open.empty()) {
    auto [g, u] = open.top();
    open.pop();
    if (g != nodes_[u].g) continue;
    for (int e = nodes_[u].edge_head; e != kNone; e = edges_[e].next) {
      const int w = edges_[e].to;
      const int64_t candidate = g + edges_[e].cost;
      if (candidate < nodes_[w].g) {
        nodes_[w].g = candidate;
        nodes_[w].parent = u;
        open.push({candidate, w});
      }
    }
  }
}

MapfSolution LacamSolver::Backtrack(int node) const {
  std::vector<int> chain;
  for (int v = node; v != kNone; v = nodes_[v].parent) chain.push_back(v);
  std::reverse(chain.begin(), chain.end());
  MapfSolution solution;
  solution.paths.assign(n_, std::vector<int>(chain.size()));
  for (size_t t = 0; t < chain.size(); ++t) {
    const int* q = Config(chain[t]);
    for (int i = 0; i < n_; ++i) solution.paths[i][t] = q[i];
  }
  return solution;
}

absl::StatusOr<MapfResult> LacamSolver::Solve(const MapfInstance& instance,
                                              const MapfStopCondition& stop,
                                              const MapfPlanObserver& on_plan) {
  if (absl::Status s = params_.Validate(); !s.ok()) return s;
  if (absl::Status s = ValidateSolveInput(instance, stop); !s.ok()) return s;
  const MapfStopwatch watch(stop);
  instance_ = instance;
  n_ = instance.num_agents();
  rng_state_ = params_.seed;
  const GridGraph& g = *instance_.graph;

  tables_.clear();
  tables_.reserve(n_);
  for (int i = 0; i < n_; ++i) tables_.emplace_back(g, instance_.goals[i]);
  nodes_.clear();
  config_.clear();
  order_.clear();
  priority_.clear();
  low_.clear();
  edges_.clear();
  explored_.clear();
  next_.assign(n_, kNone);
  occupied_now_.assign(g.size(), kNone);
  occupied_next_.assign(g.size(), kNone);
  candidates_.assign(static_cast<size_t>(n_) * 5, kNone);

  next_ = instance_.starts;
  bool is_new = false;
  const int root = InternNode(kNone, &is_new);
  nodes_[root].g = 0;
  next_.assign(n_, kNone);

  std::vector<int> open;
  open.push_back(root);
  int goal_node = kNone;
  MapfResult result;
  result.solver = "lacam";
  int64_t best_cost = -1;
  bool capped = false;
  auto is_goal = [&](int node) {
    return std::memcmp(Config(node), instance_.goals.data(), sizeof(int) * n_) == 0;
  };
  auto record_goal = [&] {
    if (goal_node == kNone) return;
    if (best_cost < 0 || nodes_[goal_node].g < best_cost) {
      best_cost = nodes_[goal_node].g;
      result.final_ms = watch.ElapsedMs();
      if (on_plan) {
        result.solution = Backtrack(goal_node);
        on_plan(result);
      }
    }
  };

  int64_t iterations = 0;
  bool stopped = false;
  while (!open.empty()) {
    if ((++iterations & 15) == 0 || goal_node != kNone) {
      if (watch.ShouldStop()) {
        stopped = true;
        break;
      }
    }
    const int node = open.back();
    if (goal_node == kNone && is_goal(node)) {
      goal_node = node;
      result.first_solution_ms = watch.ElapsedMs();
      record_goal();
      if (!params_.anytime) break;
    }
    if (goal_node != kNone && nodes_[node].g + nodes_[node].h >= nodes_[goal_node].g) {
      open.pop_back();
      continue;
    }
    const int low = nodes_[node].low_head;
    if (low == kNone) {
      open.pop_back();
      continue;
    }
    nodes_[node].low_head = low_[low].next;
    if (nodes_[node].low_head == kNone) nodes_[node].low_tail = kNone;
    ++result.expanded_nodes;

    // Lazily add the successors of this constraint: the next agent in order, at every
    // vertex it can take.
    const int depth = low_[low].depth;
    if (depth < n_) {
      const int i = order_[nodes_[node].offset + depth];
      const int v = Config(node)[i];
      int options[5];
      int k = 0;
      for (int e = 0; e < g.Degree(v); ++e) options[k++] = g.Neighbor(v, e);
      options[k++] = v;
      Shuffle(options, k);
      for (int a = 0; a < k; ++a) PushLow(node, low, i, options[a], depth + 1);
    }
    if (!Generate(node, low)) continue;
    if (static_cast<int64_t>(config_.size()) + n_ > params_.max_stored_agent_states) {
      capped = true;
      break;
    }
    const int child = InternNode(node, &is_new);
    if (is_new) {
      nodes_[child].g = nodes_[node].g + EdgeCost(node, child);
      AddEdge(node, child);
      open.push_back(child);
    } else {
      AddEdge(node, child);
      const int64_t before = nodes_[child].g;
      if (nodes_[node].g + EdgeCost(node, child) < before) {
        nodes_[child].g = nodes_[node].g + EdgeCost(node, child);
        nodes_[child].parent = node;
        Rewire(child);
        record_goal();
      }
      if (goal_node == kNone || nodes_[child].g + nodes_[child].h < nodes_[goal_node].g) {
        open.push_back(child);
      }
    }
  }
  if (goal_node == kNone) {
    if (capped) return absl::ResourceExhaustedError("lacam: memory cap reached before a plan");
    if (!stopped) return absl::NotFoundError("lacam: no plan exists (search space exhausted)");
    return watch.NoPlanStatus("lacam");
  }
  result.proven_optimal = !stopped && !capped && params_.anytime;
  result.solution = Backtrack(goal_node);
  return result;
}

}  // namespace fleetnav::planner
