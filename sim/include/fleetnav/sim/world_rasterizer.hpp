#pragma once

#include "absl/status/statusor.h"
#include "fleetnav/core/occupancy_grid.hpp"
#include "fleetnav/core/stripe_marker.hpp"
#include "fleetnav/sim/world_description.hpp"

namespace fleetnav::sim {

/// The occupancy grid of a world: a cell is occupied when its centre lies inside a box or
/// cylinder, free otherwise; the grid covers the world's extent with its origin at the min
/// corner.
absl::StatusOr<OccupancyGrid> RasterizeWorld(const WorldDescription& world, double resolution_m);

/// The world's stripe markers as the marker set of map `map_id`.
MarkerSet MarkerSetOf(const WorldDescription& world, const std::string& map_id);

}  // namespace fleetnav::sim
