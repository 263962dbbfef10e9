#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "fleetnav/planner/grid/movingai.hpp"

namespace fleetnav::planner {

/// The 4-connected graph of the passable cells of a grid, the site graph of the multi-robot
/// planners (the standard MAPF grid model of Stern et al., "Multi-Agent Pathfinding:
/// Definitions, Variants, and Benchmarks", SoCS 2019). Vertices are numbered 0..size()-1 in
/// row-major cell order; neighbours are stored in one flat array, four slots per vertex, unused
/// slots are -1. Immutable after construction; safe to share between threads.
class GridGraph {
 public:
  static constexpr int kNone = -1;

  explicit GridGraph(const MovingAiMap& map);

  int width() const { return width_; }
  int height() const { return height_; }
  int size() const { return static_cast<int>(cell_of_vertex_.size()); }
  /// Vertex of cell (x, y), or kNone for a blocked or outside cell.
  int VertexAt(int x, int y) const {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return kNone;
    return vertex_of_cell_[static_cast<size_t>(y) * width_ + x];
  }
  int X(int v) const { return cell_of_vertex_[v] % width_; }
  int Y(int v) const { return cell_of_vertex_[v] / width_; }
  int Degree(int v) const { return degree_[v]; }
  /// The k-th neighbour of v, k < Degree(v).
  int Neighbor(int v, int k) const { return neighbors_[static_cast<size_t>(v) * 4 + k]; }
  bool Adjacent(int u, int v) const;
  /// Connected-component label of every vertex (labels 0..).
  std::vector<int> ComponentLabels() const;

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<int> vertex_of_cell_;
  std::vector<int> cell_of_vertex_;
  std::vector<int> neighbors_;
  std::vector<uint8_t> degree_;
};

/// Shortest-path distances (in moves) from every vertex to one goal, computed lazily by a
/// breadth-first search from the goal that is resumed only as far as a query needs (the lazy
/// tables of LaCAM, Okumura AAAI 2023). Unreachable vertices have distance kUnreachable. Flat
/// arrays, no allocation after construction. Not thread-safe (queries mutate the frontier).
class DistanceTable {
 public:
  static constexpr int kUnreachable = 1 << 29;

  DistanceTable(const GridGraph& graph, int goal);
  int goal() const { return goal_; }
  int Get(int v);

 private:
  const GridGraph* graph_;
  int goal_;
  std::vector<int> dist_;
  std::vector<int> queue_;
  size_t head_ = 0;
};

}  // namespace fleetnav::planner
