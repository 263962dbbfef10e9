#pragma once

#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "fleetnav/core/occupancy_grid.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/core/stripe_marker.hpp"

namespace fleetnav::ctl {

/// What `fleetnavctl map render` draws: one map version with, when the site has them, its
/// stripe markers and the routes on it.
struct SiteDrawing {
  OccupancyGrid grid;
  std::optional<MarkerSet> markers;
  std::vector<Route> routes;
};

struct MapRenderParams {
  /// Pixels per grid cell; 0 picks one so that the longer side is about 1600 px (1 to 8).
  int pixels_per_cell = 0;
};

/// The pixel size RenderSiteMapPng uses for `grid` with `params`.
int PixelsPerCell(const OccupancyGrid& grid, const MapRenderParams& params);

/// Draws the site as a PNG: cells in map_server's greys (free white, occupied black, unknown
/// grey 205, values in between shaded), markers as their stripes (calibration gold, follow
/// stripes blue, charger stripes green) and each route in its own colour with a legend. A route
/// is drawn where it is anchored to the map: free-navigation waypoints and goals (a dot and a
/// heading tick) and the stripes its stripe-navigation legs follow. Turns, straights and fence
/// legs are relative to where the robot stands when the job starts, so they have no place on
/// the map and are not drawn. InvalidArgument when the path does not end in ".png" or pixels
/// per cell is outside 0..64; Internal when cairo cannot write the file.
absl::Status RenderSiteMapPng(const SiteDrawing& drawing, const std::string& png_path,
                              const MapRenderParams& params = {});

}  // namespace fleetnav::ctl
