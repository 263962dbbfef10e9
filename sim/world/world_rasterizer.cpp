#include "fleetnav/sim/world_rasterizer.hpp"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"

namespace fleetnav::sim {
namespace {

bool InsideBox(const BoxObstacle& box, const Eigen::Vector2d& p) {
  const Eigen::Vector2d d = p - box.center_m;
  const double c = std::cos(box.yaw_rad), s = std::sin(box.yaw_rad);
  const double local_x = c * d.x() + s * d.y();
  const double local_y = -s * d.x() + c * d.y();
  return std::abs(local_x) <= 0.5 * box.size_m.x() && std::abs(local_y) <= 0.5 * box.size_m.y();
}

/// A disc overlaps the square cell centred at `cell_centre`. Cylinders thinner than a cell
/// (a trolley's legs, 2 cm on a 5 cm map) may cover no cell's centre; a map built by a laser
/// shows them all the same, so every cell they touch is marked.
bool DiscMeetsCell(const CylinderObstacle& c, const Eigen::Vector2d& cell_centre,
                   double resolution_m) {
  const Eigen::Vector2d half = Eigen::Vector2d::Constant(0.5 * resolution_m);
  const Eigen::Vector2d nearest =
      c.center_m.cwiseMax(cell_centre - half).cwiseMin(cell_centre + half);
  return (nearest - c.center_m).norm() <= c.radius_m;
}

}  // namespace

absl::StatusOr<OccupancyGrid> RasterizeWorld(const WorldDescription& world, double resolution_m) {
  if (!std::isfinite(resolution_m) || resolution_m <= 0.0) {
    return absl::InvalidArgumentError(
        absl::StrCat("resolution_m: must be finite and > 0, got ", resolution_m));
  }
  const Eigen::Vector2d size = world.max_corner_m - world.min_corner_m;
  const int width = static_cast<int>(std::ceil(size.x() / resolution_m - 1e-9));
  const int height = static_cast<int>(std::ceil(size.y() / resolution_m - 1e-9));
  ASSIGN_OR_RETURN(OccupancyGrid grid,
                   OccupancyGrid::Filled(width, height, resolution_m,
                                         Pose2(world.min_corner_m.x(), world.min_corner_m.y(), 0),
                                         OccupancyGrid::kFreeValue));
  // The trolleys' legs stand where the world file puts them.
  std::vector<CylinderObstacle> cylinders = world.cylinders;
  for (const Trolley& trolley : world.trolleys) {
    for (const Eigen::Vector2d& leg : trolley.LegsInTrolley()) {
      cylinders.push_back(
          {"trolley_leg", trolley.pose().TransformPoint(leg), trolley.leg_radius_m, 1.0});
    }
  }
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const Eigen::Vector2d p = grid.CellToWorld({x, y});
      bool occupied = false;
      for (const BoxObstacle& box : world.boxes) occupied = occupied || InsideBox(box, p);
      for (const CylinderObstacle& c : cylinders) {
        occupied = occupied || (p - c.center_m).norm() <= c.radius_m ||
                   (c.radius_m < resolution_m && DiscMeetsCell(c, p, resolution_m));
      }
      if (occupied) grid.SetValue({x, y}, OccupancyGrid::kOccupiedValue);
    }
  }
  return grid;
}

MarkerSet MarkerSetOf(const WorldDescription& world, const std::string& map_id) {
  MarkerSet set;
  set.map_id = map_id;
  set.markers = world.markers;
  // Each straight piece of a follow or charger stripe, numbered after the markers, tied to its
  // stripe by stripe_id: the agent knows where a stripe ends and tells an end from a gap.
  int next_id = 0;
  for (const StripeMarker& m : set.markers) next_id = std::max(next_id, m.id);
  for (const FloorStripe& stripe : world.stripes) {
    for (size_t i = 0; i + 1 < stripe.points_m.size(); ++i) {
      const Eigen::Vector2d a = stripe.points_m[i], b = stripe.points_m[i + 1];
      StripeMarker piece;
      piece.id = ++next_id;
      piece.position_m = 0.5 * (a + b);
      piece.yaw_rad = NormalizeMarkerYaw(std::atan2(b.y() - a.y(), b.x() - a.x()));
      piece.length_m = (b - a).norm();
      piece.kind = stripe.charger ? MarkerKind::kChargerStripe : MarkerKind::kFollowStripe;
      piece.stripe_id = stripe.id;
      if (piece.length_m > 0.0) set.markers.push_back(piece);
    }
  }
  // The trolleys, so that dock actions can name them and robots know where they stood.
  for (const Trolley& trolley : world.trolleys) {
    set.trolleys.push_back({trolley.id,
                            Pose2(trolley.center_m.x(), trolley.center_m.y(), trolley.yaw_rad),
                            trolley.size_m, trolley.leg_radius_m});
  }
  return set;
}

}  // namespace fleetnav::sim
