#include "fleetnav/ctl/map_render.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/map_io.hpp"

namespace fleetnav::ctl {
namespace {

struct Rgb {
  double r, g, b;
};

constexpr int kLegendRowPx = 16;

Rgb RouteColor(size_t index) {
  static const Rgb kPalette[] = {{0.85, 0.10, 0.10}, {0.10, 0.55, 0.10}, {0.60, 0.10, 0.65},
                                 {0.95, 0.45, 0.00}, {0.00, 0.55, 0.60}, {0.45, 0.25, 0.10}};
  return kPalette[index % (sizeof(kPalette) / sizeof(kPalette[0]))];
}

Rgb MarkerColor(MarkerKind kind) {
  switch (kind) {
    case MarkerKind::kFollowStripe:
      return {0.15, 0.35, 0.90};
    case MarkerKind::kChargerStripe:
      return {0.10, 0.70, 0.30};
    case MarkerKind::kCalibration:
      break;
  }
  return {0.90, 0.70, 0.00};
}

/// The cells, one image pixel each, in cairo's RGB24 layout with the top row first.
cairo_surface_t* CellSurface(const OccupancyGrid& grid) {
  cairo_surface_t* cells =
      cairo_image_surface_create(CAIRO_FORMAT_RGB24, grid.width(), grid.height());
  cairo_surface_flush(cells);
  unsigned char* data = cairo_image_surface_get_data(cells);
  const int stride = cairo_image_surface_get_stride(cells);
  for (int y = 0; y < grid.height(); ++y) {
    auto* row =
        reinterpret_cast<uint32_t*>(data + static_cast<size_t>(stride) * (grid.height() - 1 - y));
    for (int x = 0; x < grid.width(); ++x) {
      const uint32_t grey = MapServerGrey(grid.Value({x, y}));
      row[x] = (grey << 16) | (grey << 8) | grey;
    }
  }
  cairo_surface_mark_dirty(cells);
  return cells;
}

/// Maps map-frame metres to image pixels: through the grid's origin into cell units, then
/// y flipped so that the grid's row 0 is the image's bottom row.
class PixelFrame {
 public:
  PixelFrame(const OccupancyGrid& grid, int pixels_per_cell)
      : map_to_grid_(grid.origin().Inverse()),
        pixels_per_m_(pixels_per_cell / grid.resolution_m()),
        height_px_(grid.height() * pixels_per_cell) {}

  void MoveTo(cairo_t* cr, const Eigen::Vector2d& point_m) const {
    const Eigen::Vector2d p = ToPixel(point_m);
    cairo_move_to(cr, p.x(), p.y());
  }
  void LineTo(cairo_t* cr, const Eigen::Vector2d& point_m) const {
    const Eigen::Vector2d p = ToPixel(point_m);
    cairo_line_to(cr, p.x(), p.y());
  }
  Eigen::Vector2d ToPixel(const Eigen::Vector2d& point_m) const {
    const Eigen::Vector2d in_grid = map_to_grid_.TransformPoint(point_m);
    return {in_grid.x() * pixels_per_m_, height_px_ - in_grid.y() * pixels_per_m_};
  }
  double Pixels(double metres) const { return metres * pixels_per_m_; }

 private:
  Pose2 map_to_grid_;
  double pixels_per_m_;
  double height_px_;
};

void DrawMarkers(cairo_t* cr, const PixelFrame& frame, const MarkerSet& markers) {
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
  for (const StripeMarker& marker : markers.markers) {
    const Rgb c = MarkerColor(marker.kind);
    const Eigen::Vector2d half =
        0.5 * marker.length_m * Eigen::Vector2d(std::cos(marker.yaw_rad), std::sin(marker.yaw_rad));
    cairo_set_source_rgb(cr, c.r, c.g, c.b);
    cairo_set_line_width(cr, std::max(3.0, frame.Pixels(0.05)));
    frame.MoveTo(cr, marker.position_m - half);
    frame.LineTo(cr, marker.position_m + half);
    cairo_stroke(cr);
  }
}

/// The map-anchored parts of a route: free-navigation waypoints and goals joined in order
/// (a dot at each goal with a tick along its heading), and the markers of followed stripes.
void DrawRoute(cairo_t* cr, const PixelFrame& frame, const Route& route,
               const std::optional<MarkerSet>& markers, const Rgb& c) {
  cairo_set_source_rgb(cr, c.r, c.g, c.b);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  std::optional<Eigen::Vector2d> last;
  const auto visit = [&](const Eigen::Vector2d& p) {
    if (last) {
      cairo_set_line_width(cr, 2.0);
      frame.MoveTo(cr, *last);
      frame.LineTo(cr, p);
      cairo_stroke(cr);
    }
    last = p;
  };
  for (const RouteAction& action : route.actions) {
    if (const auto* nav = std::get_if<FreeNavigationAction>(&action.params)) {
      for (const Eigen::Vector2d& waypoint : nav->waypoints_m) visit(waypoint);
      const Eigen::Vector2d goal = nav->goal.translation();
      visit(goal);
      const Eigen::Vector2d pixel = frame.ToPixel(goal);
      cairo_arc(cr, pixel.x(), pixel.y(), 4.0, 0, 2 * kPi);
      cairo_fill(cr);
      const double tick_m = std::max(0.3, 10.0 / frame.Pixels(1.0));
      frame.MoveTo(cr, goal);
      frame.LineTo(cr, goal + tick_m * Eigen::Vector2d(std::cos(nav->goal.yaw_rad()),
                                                       std::sin(nav->goal.yaw_rad())));
      cairo_stroke(cr);
    } else if (const auto* stripe = std::get_if<StripeNavigationAction>(&action.params)) {
      if (!markers) continue;
      for (const StripeMarker& marker : markers->markers) {
        if (marker.stripe_id != stripe->stripe_id) continue;
        const Eigen::Vector2d half =
            0.5 * marker.length_m *
            Eigen::Vector2d(std::cos(marker.yaw_rad), std::sin(marker.yaw_rad));
        cairo_set_line_width(cr, std::max(6.0, frame.Pixels(0.1)));
        frame.MoveTo(cr, marker.position_m - half);
        frame.LineTo(cr, marker.position_m + half);
        cairo_stroke(cr);
      }
    } else {
      last.reset();  // a relative action: the next anchored point starts a new line
    }
  }
}

void DrawLegend(cairo_t* cr, const std::vector<Route>& routes) {
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, 12.0);
  for (size_t i = 0; i < routes.size(); ++i) {
    const Rgb c = RouteColor(i);
    const double y = 4.0 + kLegendRowPx * static_cast<double>(i);
    cairo_set_source_rgba(cr, 1, 1, 1, 0.8);
    cairo_rectangle(cr, 2, y - 2, 220, kLegendRowPx);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, c.r, c.g, c.b);
    cairo_rectangle(cr, 6, y + 2, 10, 10);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_move_to(cr, 22, y + 11);
    cairo_show_text(cr, routes[i].name.c_str());
  }
}

}  // namespace

int PixelsPerCell(const OccupancyGrid& grid, const MapRenderParams& params) {
  if (params.pixels_per_cell > 0) return params.pixels_per_cell;
  const int longer_side = std::max(grid.width(), grid.height());
  return std::clamp(1600 / longer_side, 1, 8);
}

absl::Status RenderSiteMapPng(const SiteDrawing& drawing, const std::string& png_path,
                              const MapRenderParams& params) {
  if (!absl::EndsWith(png_path, ".png")) {
    return absl::InvalidArgumentError(
        absl::StrCat("render: '", png_path, "' must end in .png (the only format written)"));
  }
  if (params.pixels_per_cell < 0 || params.pixels_per_cell > 64) {
    return absl::InvalidArgumentError(
        absl::StrCat("render: pixels per cell must be in 1..64 (or 0 for automatic), got ",
                     params.pixels_per_cell));
  }
  const OccupancyGrid& grid = drawing.grid;
  const int scale = PixelsPerCell(grid, params);
  cairo_surface_t* surface =
      cairo_image_surface_create(CAIRO_FORMAT_RGB24, grid.width() * scale, grid.height() * scale);
  cairo_t* cr = cairo_create(surface);

  cairo_surface_t* cells = CellSurface(grid);
  cairo_save(cr);
  cairo_scale(cr, scale, scale);
  cairo_set_source_surface(cr, cells, 0, 0);
  cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
  cairo_paint(cr);
  cairo_restore(cr);
  cairo_surface_destroy(cells);

  const PixelFrame frame(grid, scale);
  if (drawing.markers) DrawMarkers(cr, frame, *drawing.markers);
  for (size_t i = 0; i < drawing.routes.size(); ++i) {
    DrawRoute(cr, frame, drawing.routes[i], drawing.markers, RouteColor(i));
  }
  DrawLegend(cr, drawing.routes);

  cairo_destroy(cr);
  cairo_surface_flush(surface);
  cairo_status_t status = cairo_surface_status(surface);
  if (status == CAIRO_STATUS_SUCCESS)
    status = cairo_surface_write_to_png(surface, png_path.c_str());
  cairo_surface_destroy(surface);
  if (status != CAIRO_STATUS_SUCCESS) {
    return absl::InternalError(
        absl::StrCat("render: cannot write '", png_path, "': ", cairo_status_to_string(status)));
  }
  return absl::OkStatus();
}

}  // namespace fleetnav::ctl
