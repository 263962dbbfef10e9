#include "fleetnav/planner/mapf/sipp.hpp"

#include <algorithm>
#include <functional>
#include <queue>
#include <tuple>

#include "absl/container/flat_hash_map.h"
#include "absl/strings/str_cat.h"

namespace fleetnav::planner {
namespace {

constexpr int kNone = -1;

struct OpenEntry {
  int f;
  int neg_step;
  int id;
  bool operator>(const OpenEntry& o) const {
    return std::tie(f, neg_step, id) > std::tie(o.f, o.neg_step, o.id);
  }
};

struct FocalEntry {
  int conflicts;
  int f;
  int neg_step;
  int id;
  bool operator>(const FocalEntry& o) const {
    return std::tie(conflicts, f, neg_step, id) > std::tie(o.conflicts, o.f, o.neg_step, o.id);
  }
};

// With w = 1 one queue suffices: the lowest f, then the fewest conflicts.
struct ExactEntry {
  int f;
  int conflicts;
  int neg_step;
  int id;
  bool operator>(const ExactEntry& o) const {
    return std::tie(f, conflicts, neg_step, id) > std::tie(o.f, o.conflicts, o.neg_step, o.id);
  }
};

template <typename T>
using MinQueue = std::priority_queue<T, std::vector<T>, std::greater<T>>;

}  // namespace

int& SippPlanner::BestSlot(int v, int interval, bool terminal) {
  if (interval >= kDenseIntervals) {
    const int64_t key = ((static_cast<int64_t>(v) << 32) | static_cast<uint32_t>(interval)) * 2 +
                        (terminal ? 1 : 0);
    return overflow_.try_emplace(key, -1).first->second;
  }
  const size_t k = (static_cast<size_t>(v) * kDenseIntervals + interval) * 2 + (terminal ? 1 : 0);
  if (slot_stamp_[k] != generation_) {
    slot_stamp_[k] = generation_;
    slot_[k] = -1;
  }
  return slot_[k];
}

absl::StatusOr<SippResult> SippPlanner::Plan(const SippRequest& request, ConstraintTable& table,
                                             DistanceTable& distance_to_goal) {
  nodes_.clear();
  overflow_.clear();
  const size_t slots = static_cast<size_t>(graph_.size()) * kDenseIntervals * 2;
  if (slot_.size() != slots) {
    slot_.assign(slots, -1);
    slot_stamp_.assign(slots, 0);
  }
  if (++generation_ == 0) {  // wrapped: forget every stamp
    std::fill(slot_stamp_.begin(), slot_stamp_.end(), 0);
    generation_ = 1;
  }
  const int h0 = distance_to_goal.Get(request.start);
  if (h0 >= DistanceTable::kUnreachable) {
    return absl::NotFoundError(
        absl::StrCat("sipp: goal ", request.goal, " unreachable from ", request.start));
  }
  const std::vector<SafeInterval>& start_intervals = table.Intervals(request.start);
  int start_interval = kNone;
  for (int k = 0; k < static_cast<int>(start_intervals.size()); ++k) {
    const SafeInterval& s = start_intervals[k];
    if (s.begin_step <= request.start_step && request.start_step < s.end_step) {
      start_interval = k;
      break;
    }
  }
  if (start_interval == kNone) {
    return absl::NotFoundError(absl::StrCat("sipp: start vertex ", request.start,
                                            " is reserved at step ", request.start_step));
  }

  MinQueue<OpenEntry> open;
  MinQueue<OpenEntry> pending;  // open nodes above the focal bound, by f
  MinQueue<FocalEntry> focal;
  MinQueue<ExactEntry> exact;  // used instead of the three above when w = 1
  const bool is_exact = request.suboptimality <= 1.0;
  const int f0 = request.start_step + h0;
  const double w = request.suboptimality;
  double bound = w * f0;

  auto push = [&](const Node& n) {
    // A copy that is neither later nor more conflicting than a known one is dropped; one that
    // is both no later and no more conflicting supersedes it.
    int& best = BestSlot(n.v, n.interval, n.terminal);
    if (best >= 0) {
      Node& known = nodes_[best];
      if (known.step <= n.step && known.conflicts <= n.conflicts) return;
      if (n.step <= known.step && n.conflicts <= known.conflicts) known.closed = true;
    }
    const int id = static_cast<int>(nodes_.size());
    best = id;
    nodes_.push_back(n);
    if (is_exact) {
      exact.push({n.f, n.conflicts, -n.step, id});
      return;
    }
    open.push({n.f, -n.step, id});
    if (n.f <= bound) {
      focal.push({n.conflicts, n.f, -n.step, id});
    } else {
      pending.push({n.f, -n.step, id});
    }
  };
  push({request.start, start_interval, request.start_step,
        start_intervals[start_interval].conflicts, f0, kNone, false, false});

  SippResult result;
  // The next node to expand and the lowest f in OPEN, or -1 when OPEN is empty.
  auto select = [&](int* f_min) -> int {
    if (is_exact) {
      while (!exact.empty() && nodes_[exact.top().id].closed) exact.pop();
      if (exact.empty()) return kNone;
      *f_min = exact.top().f;
      const int id = exact.top().id;
      exact.pop();
      return id;
    }
    while (!open.empty() && nodes_[open.top().id].closed) open.pop();
    if (open.empty()) return kNone;
    *f_min = open.top().f;
    if (w * *f_min > bound) bound = w * *f_min;
    while (!pending.empty() && pending.top().f <= bound) {
      const int id = pending.top().id;
      pending.pop();
      if (!nodes_[id].closed)
        focal.push({nodes_[id].conflicts, nodes_[id].f, -nodes_[id].step, id});
    }
    while (!focal.empty() && nodes_[focal.top().id].closed) focal.pop();
    if (focal.empty()) {
      // Every open node lies above the bound (only possible through rounding): take OPEN's.
      const int id = open.top().id;
      focal.push({nodes_[id].conflicts, nodes_[id].f, -nodes_[id].step, id});
    }
    const int id = focal.top().id;
    focal.pop();
    return id;
  };

  while (true) {
    int f_min = 0;
    const int id = select(&f_min);
    if (id == kNone) {
      return absl::NotFoundError(absl::StrCat("sipp: no path from ", request.start, " to ",
                                              request.goal, " under the reservations"));
    }
    nodes_[id].closed = true;
    if (++result.expanded > request.max_expansions) {
      return absl::ResourceExhaustedError(
          absl::StrCat("sipp: expansion cap ", request.max_expansions, " reached"));
    }
    const Node cur = nodes_[id];
    if (cur.terminal) {
      // Rebuild the step-by-step path: a node's vertex holds from its arrival until the next.
      std::vector<int> chain;
      for (int k = id; k != kNone; k = nodes_[k].parent) chain.push_back(k);
      std::reverse(chain.begin(), chain.end());
      result.path.assign(cur.step - request.start_step + 1, request.goal);
      for (size_t k = 0; k < chain.size(); ++k) {
        const Node& a = nodes_[chain[k]];
        const int until = k + 1 < chain.size() ? nodes_[chain[k + 1]].step : cur.step + 1;
        for (int s = a.step; s < until; ++s) result.path[s - request.start_step] = a.v;
      }
      result.arrival_step = cur.step;
      result.lower_bound_step = std::max(f_min, f0);
      result.conflicts = cur.conflicts;
      return result;
    }
    const std::vector<SafeInterval>& here = table.Intervals(cur.v);
    const SafeInterval iv = here[cur.interval];
    if (cur.v == request.goal) {
      // The goal is reached where every later interval follows without a gap to for ever.
      int extra = 0;
      int k = cur.interval;
      while (k + 1 < static_cast<int>(here.size()) && here[k + 1].begin_step == here[k].end_step) {
        extra += here[++k].conflicts;
      }
      if (here[k].end_step == ConstraintTable::kForever) {
        push({cur.v, cur.interval, cur.step, cur.conflicts + extra, cur.step, id, true, false});
      }
    }
    // Wait into the next interval of this vertex when it follows without a gap.
    if (cur.interval + 1 < static_cast<int>(here.size()) &&
        here[cur.interval + 1].begin_step == iv.end_step) {
      const SafeInterval& next = here[cur.interval + 1];
      push({cur.v, cur.interval + 1, next.begin_step, cur.conflicts + next.conflicts,
            next.begin_step + distance_to_goal.Get(cur.v), id, false, false});
    }
    // Moves: arrive at a neighbour in each of its intervals reachable while still safe here.
    const int latest_arrival = iv.end_step;  // leave at end_step − 1 at the latest
    for (int n = 0; n < graph_.Degree(cur.v); ++n) {
      const int v = graph_.Neighbor(cur.v, n);
      const int h = distance_to_goal.Get(v);
      if (h >= DistanceTable::kUnreachable) continue;
      const std::vector<SafeInterval>& there = table.Intervals(v);
      auto first =
          std::upper_bound(there.begin(), there.end(), cur.step + 1,
                           [](int step, const SafeInterval& s) { return step < s.end_step; });
      for (auto it = first; it != there.end(); ++it) {
        if (it->begin_step > latest_arrival) break;
        int arrive = std::max(cur.step + 1, it->begin_step);
        const int last = std::min(it->end_step - 1, latest_arrival);
        // With no_following the vertex must also be free the step before the arrival.
        auto following = [&](int step) {
          return request.no_following && step - 1 < it->begin_step &&
                 !(it != there.begin() && (it - 1)->end_step == it->begin_step);
        };
        while (arrive <= last && (table.HardEdgeBlocked(cur.v, v, arrive) || following(arrive))) {
          ++arrive;
        }
        if (arrive > last) continue;
        const int conflicts =
            cur.conflicts + it->conflicts + table.SoftEdgeConflicts(cur.v, v, arrive);
        push({v, static_cast<int>(it - there.begin()), arrive, conflicts, arrive + h, id, false,
              false});
      }
    }
  }
}

}  // namespace fleetnav::planner
