#include "fleetnav/planner/mapf/constraint_table.hpp"

#include <algorithm>

namespace fleetnav::planner {
namespace {

// Removes one occurrence of `value` from `values` (no-op when absent).
template <typename T>
void EraseOne(std::vector<T>& values, const T& value) {
  auto it = std::find(values.begin(), values.end(), value);
  if (it != values.end()) {
    *it = values.back();
    values.pop_back();
  }
}

}  // namespace

ConstraintTable::ConstraintTable(int num_vertices) : vertices_(num_vertices) {}

ConstraintTable::VertexRecord& ConstraintTable::Touch(int v) {
  VertexRecord& r = vertices_[v];
  if (!r.touched) {
    r.touched = true;
    touched_.push_back(v);
  }
  r.intervals_valid = false;
  return r;
}

void ConstraintTable::Clear() {
  for (int v : touched_) {
    VertexRecord& r = vertices_[v];
    r.hard_steps.clear();
    r.hard_park_steps.clear();
    r.soft_steps.clear();
    r.soft_park_steps.clear();
    r.hard_in_moves.clear();
    r.soft_in_moves.clear();
    r.touched = false;
    r.intervals_valid = false;
  }
  touched_.clear();
}

void ConstraintTable::AddHardVertex(int v, int step) { Touch(v).hard_steps.push_back(step); }

void ConstraintTable::AddHardEdge(int from, int to, int step) {
  vertices_[to].hard_in_moves.emplace_back(from, step);
  Touch(to);
}

void ConstraintTable::AddHardPath(const std::vector<int>& path, int start_step, bool park) {
  ChangePath(path, start_step, park, /*hard=*/true, +1);
}

void ConstraintTable::RemoveHardPath(const std::vector<int>& path, int start_step, bool park) {
  ChangePath(path, start_step, park, /*hard=*/true, -1);
}

void ConstraintTable::AddSoftPath(const std::vector<int>& path, int start_step, bool park) {
  ChangePath(path, start_step, park, /*hard=*/false, +1);
}

void ConstraintTable::ChangePath(const std::vector<int>& path, int start_step, bool park, bool hard,
                                 int delta) {
  if (path.empty()) return;
  const int last = static_cast<int>(path.size()) - 1;
  for (int k = 0; k <= last; ++k) {
    const int step = start_step + k;
    VertexRecord& r = Touch(path[k]);
    const bool parked_here = park && k == last;
    std::vector<int>& steps = parked_here ? (hard ? r.hard_park_steps : r.soft_park_steps)
                                          : (hard ? r.hard_steps : r.soft_steps);
    if (delta > 0) {
      steps.push_back(step);
    } else {
      EraseOne(steps, step);
    }
    if (k == 0 || path[k - 1] == path[k]) continue;
    // Moving path[k-1] → path[k] blocks the opposite move arriving at the same step.
    VertexRecord& back = Touch(path[k - 1]);
    auto& moves = hard ? back.hard_in_moves : back.soft_in_moves;
    const std::pair<int, int> swap{path[k], step};
    if (delta > 0) {
      moves.push_back(swap);
    } else {
      EraseOne(moves, swap);
    }
  }
}

bool ConstraintTable::HardEdgeBlocked(int from, int to, int step) const {
  for (const auto& [f, s] : vertices_[to].hard_in_moves) {
    if (f == from && s == step) return true;
  }
  return false;
}

int ConstraintTable::SoftEdgeConflicts(int from, int to, int step) const {
  int count = 0;
  for (const auto& [f, s] : vertices_[to].soft_in_moves) count += f == from && s == step;
  return count;
}

const std::vector<SafeInterval>& ConstraintTable::Intervals(int v) {
  VertexRecord& r = vertices_[v];
  if (!r.intervals_valid) {
    BuildIntervals(r);
    r.intervals_valid = true;
  }
  return r.intervals;
}

void ConstraintTable::BuildIntervals(VertexRecord& r) {
  r.intervals.clear();
  int hard_end = kForever;
  for (int s : r.hard_park_steps) hard_end = std::min(hard_end, s);
  std::sort(r.hard_steps.begin(), r.hard_steps.end());
  std::sort(r.soft_steps.begin(), r.soft_steps.end());
  std::sort(r.soft_park_steps.begin(), r.soft_park_steps.end());
  // Cut points: every hard or soft step and the step after it, every soft parking step.
  std::vector<int> cuts = {0};
  for (int s : r.hard_steps) {
    cuts.push_back(s);
    cuts.push_back(s + 1);
  }
  for (int s : r.soft_steps) {
    cuts.push_back(s);
    cuts.push_back(s + 1);
  }
  for (int s : r.soft_park_steps) cuts.push_back(s);
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
  while (!cuts.empty() && cuts.back() >= hard_end) cuts.pop_back();
  for (size_t k = 0; k < cuts.size(); ++k) {
    const int begin = cuts[k];
    if (begin < 0) continue;
    const int end = k + 1 < cuts.size() ? cuts[k + 1] : hard_end;
    if (std::binary_search(r.hard_steps.begin(), r.hard_steps.end(), begin)) continue;
    const auto soft_range = std::equal_range(r.soft_steps.begin(), r.soft_steps.end(), begin);
    const int soft_here = static_cast<int>(soft_range.second - soft_range.first);
    const int parked = static_cast<int>(
        std::upper_bound(r.soft_park_steps.begin(), r.soft_park_steps.end(), begin) -
        r.soft_park_steps.begin());
    const int conflicts = soft_here + parked;
    // Stretches without a soft step merge with a contiguous predecessor of equal count.
    if (soft_here == 0 && !r.intervals.empty()) {
      SafeInterval& prev = r.intervals.back();
      const bool prev_has_soft_step =
          std::binary_search(r.soft_steps.begin(), r.soft_steps.end(), prev.begin_step);
      if (prev.end_step == begin && prev.conflicts == conflicts && !prev_has_soft_step) {
        prev.end_step = end;
        continue;
      }
    }
    r.intervals.push_back({begin, end, conflicts});
  }
}

}  // namespace fleetnav::planner
