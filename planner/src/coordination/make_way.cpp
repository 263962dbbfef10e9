#include "fleetnav/planner/coordination/make_way.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <queue>
#include <utility>

#include "absl/strings/str_format.h"
#include "fleetnav/core/angles.hpp"

namespace fleetnav::planner {
namespace {

/// The smaller side of the footprint's bounding box (0 for none).
double FootprintSmallerSideM(const std::vector<Eigen::Vector2d>& footprint_m) {
  if (footprint_m.empty()) return 0.0;
  Eigen::Vector2d lo = footprint_m.front();
  Eigen::Vector2d hi = lo;
  for (const Eigen::Vector2d& v : footprint_m) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  return (hi - lo).minCoeff();
}

}  // namespace

absl::Status MakeWayParams::Validate() const {
  if (!(std::isfinite(max_distance_m) && max_distance_m > 0.0)) {
    return absl::InvalidArgumentError("max_distance_m: must be finite and > 0");
  }
  if (!(std::isfinite(candidate_step_m) && candidate_step_m > 0.0)) {
    return absl::InvalidArgumentError("candidate_step_m: must be finite and > 0");
  }
  return absl::OkStatus();
}

absl::StatusOr<Pose2> FindMakeWayPlace(Costmap& costmap, const Pose2& map_origin,
                                       const MakeWayRequestGeometry& request,
                                       const MakeWayParams& params) {
  if (absl::Status s = params.Validate(); !s.ok()) return s;
  if (!request.from_in_map.IsFinite()) {
    return absl::InvalidArgumentError("from_in_map: not finite");
  }
  const double res_m = costmap.resolution_m();
  const Pose2 from_in_grid = map_origin.Inverse() * request.from_in_map;
  const int start_x = static_cast<int>(std::floor(from_in_grid.x_m() / res_m));
  const int start_y = static_cast<int>(std::floor(from_in_grid.y_m() / res_m));
  if (!costmap.InBounds(start_x, start_y)) {
    return absl::InvalidArgumentError(
        absl::StrFormat("the robot at (%.2f, %.2f) is outside the map", request.from_in_map.x_m(),
                        request.from_in_map.y_m()));
  }
  const int stride = std::max(1, static_cast<int>(std::lround(params.candidate_step_m / res_m)));
  const double max_cells = params.max_distance_m / res_m;

  // A place: the footprint fits at one of four yaws and its grown cells meet nobody's way. Grown
  // by a cell more than the margin: the robot stops within its goal tolerance of the place and
  // is judged at its exact pose, not the cell's centre; without the slack a robot a hair inside
  // someone's way was sent 2 cm aside, arrived at once and was asked again, five times a second.
  const double margin_m = request.margin_m + request.cell_m;
  auto place_at = [&](int x, int y) -> std::optional<Pose2> {
    for (int quarter = 0; quarter < 4; ++quarter) {
      const double yaw_in_grid = NormalizeAngle(from_in_grid.yaw_rad() + quarter * kPi / 2.0);
      if (!costmap.FootprintFree(x, y, yaw_in_grid)) continue;
      const Pose2 in_map = map_origin * Pose2((x + 0.5) * res_m, (y + 0.5) * res_m, yaw_in_grid);
      const CellSet cells = CellSet::Sweep({in_map}, request.footprint_m, margin_m, request.cell_m);
      bool clear = true;
      for (const CellSet* other : request.keep_off) {
        if (other != nullptr && cells.Intersects(*other)) {
          clear = false;
          break;
        }
      }
      if (clear) return in_map;
    }
    return std::nullopt;
  };

  // Cells the robot's centre may not cross: within half its footprint's smaller side and the
  // pass margin of where another robot stands (tested at the centre and eight points that far
  // round it; each cell once).
  const int width = costmap.width();
  std::vector<int8_t> passes_someone_at;  // per cell: -1 unknown, 0 no, 1 yes
  std::vector<Eigen::Vector2d> probes;
  if (!request.impassable.empty()) {
    passes_someone_at.assign(static_cast<size_t>(width) * costmap.height(), -1);
    const double reach_m = 0.5 * FootprintSmallerSideM(request.footprint_m) + request.pass_margin_m;
    probes.emplace_back(Eigen::Vector2d::Zero());
    for (int i = 0; i < 8; ++i) {
      probes.emplace_back(reach_m * std::cos(i * kPi / 4.0), reach_m * std::sin(i * kPi / 4.0));
    }
  }
  auto passes_someone = [&](int x, int y) {
    if (request.impassable.empty()) return false;
    int8_t& known = passes_someone_at[static_cast<size_t>(y) * width + x];
    if (known < 0) {
      const Eigen::Vector2d c =
          (map_origin * Pose2((x + 0.5) * res_m, (y + 0.5) * res_m, 0.0)).translation();
      known = std::any_of(probes.begin(), probes.end(), [&](const Eigen::Vector2d& offset) {
        return std::any_of(
            request.impassable.begin(), request.impassable.end(), [&](const CellSet* other) {
              return other != nullptr && other->ContainsPoint(c + offset, request.cell_m);
            });
      });
    }
    return known == 1;
  };

  // Dijkstra from the robot's cell over cells the footprint fits in at some yaw (the start cell
  // is taken as it is: an estimate a little inside an obstacle still leaves).
  std::vector<double> distance(static_cast<size_t>(width) * costmap.height(),
                               std::numeric_limits<double>::infinity());
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  const int start = start_y * width + start_x;
  distance[start] = 0.0;
  open.push({0.0, start});
  constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  while (!open.empty()) {
    const auto [d, index] = open.top();
    open.pop();
    if (d > distance[index]) continue;
    const int x = index % width;
    const int y = index / width;
    // Places on a lattice anchored at the robot's cell, so its own place is the first tried.
    if ((x - start_x) % stride == 0 && (y - start_y) % stride == 0) {
      if (std::optional<Pose2> place = place_at(x, y)) return *place;
    }
    for (int k = 0; k < 8; ++k) {
      const int nx = x + kDx[k];
      const int ny = y + kDy[k];
      if (!costmap.InBounds(nx, ny) || !costmap.AnyYawFree(nx, ny)) continue;
      const double nd = d + (k < 4 ? 1.0 : std::sqrt(2.0));
      const int n = ny * width + nx;
      if (nd > max_cells || nd >= distance[n] || passes_someone(nx, ny)) continue;
      distance[n] = nd;
      open.push({nd, n});
    }
  }
  return absl::NotFoundError(
      absl::StrFormat("no place within %.1f m of (%.2f, %.2f) is off the other robots' ways",
                      params.max_distance_m, request.from_in_map.x_m(), request.from_in_map.y_m()));
}

}  // namespace fleetnav::planner
