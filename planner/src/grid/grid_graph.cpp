#include "fleetnav/planner/grid/grid_graph.hpp"

namespace fleetnav::planner {

GridGraph::GridGraph(const MovingAiMap& map) : width_(map.width), height_(map.height) {
  vertex_of_cell_.assign(static_cast<size_t>(width_) * height_, kNone);
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      if (!map.Passable(x, y)) continue;
      const int cell = y * width_ + x;
      vertex_of_cell_[cell] = static_cast<int>(cell_of_vertex_.size());
      cell_of_vertex_.push_back(cell);
    }
  }
  neighbors_.assign(cell_of_vertex_.size() * 4, kNone);
  degree_.assign(cell_of_vertex_.size(), 0);
  static constexpr int kDx[] = {1, 0, -1, 0};
  static constexpr int kDy[] = {0, 1, 0, -1};
  for (int v = 0; v < size(); ++v) {
    for (int k = 0; k < 4; ++k) {
      const int u = VertexAt(X(v) + kDx[k], Y(v) + kDy[k]);
      if (u != kNone) neighbors_[static_cast<size_t>(v) * 4 + degree_[v]++] = u;
    }
  }
}

bool GridGraph::Adjacent(int u, int v) const {
  for (int k = 0; k < degree_[u]; ++k) {
    if (Neighbor(u, k) == v) return true;
  }
  return false;
}

std::vector<int> GridGraph::ComponentLabels() const {
  std::vector<int> label(size(), kNone);
  std::vector<int> stack;
  int next = 0;
  for (int s = 0; s < size(); ++s) {
    if (label[s] != kNone) continue;
    label[s] = next;
    stack.push_back(s);
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      for (int k = 0; k < Degree(v); ++k) {
        const int u = Neighbor(v, k);
        if (label[u] == kNone) {
          label[u] = next;
          stack.push_back(u);
        }
      }
    }
    ++next;
  }
  return label;
}

DistanceTable::DistanceTable(const GridGraph& graph, int goal)
    : graph_(&graph), goal_(goal), dist_(graph.size(), kUnreachable) {
  queue_.reserve(graph.size());
  dist_[goal] = 0;
  queue_.push_back(goal);
}

int DistanceTable::Get(int v) {
  while (dist_[v] == kUnreachable && head_ < queue_.size()) {
    const int w = queue_[head_++];
    const int d = dist_[w] + 1;
    for (int k = 0; k < graph_->Degree(w); ++k) {
      const int u = graph_->Neighbor(w, k);
      if (dist_[u] == kUnreachable) {
        dist_[u] = d;
        queue_.push_back(u);
      }
    }
  }
  return dist_[v];
}

}  // namespace fleetnav::planner
