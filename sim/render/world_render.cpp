#include "fleetnav/sim/world_render.hpp"

#include <cairo-svg.h>
#include <cairo.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/robot_model.hpp"

namespace fleetnav::sim {
namespace {

struct Rgb {
  double r, g, b;
};

Rgb ColorOf(const std::string& kind) {
  if (kind == "wall") return {0.15, 0.15, 0.15};
  if (kind == "fence") return {0.1, 0.6, 0.2};
  if (kind == "feed_kitchen") return {0.55, 0.35, 0.15};
  if (kind == "shelf") return {0.35, 0.45, 0.7};
  if (kind == "charging_pole") return {0.1, 0.3, 0.9};
  if (kind == "parcel") return {0.75, 0.6, 0.35};
  return {0.5, 0.5, 0.5};
}

Rgb TrajectoryColor(size_t index) {
  static const Rgb kPalette[] = {{0.85, 0.1, 0.1}, {0.1, 0.3, 0.85}, {0.1, 0.6, 0.1},
                                 {0.6, 0.1, 0.6},  {0.9, 0.5, 0.0},  {0.0, 0.6, 0.6}};
  return kPalette[index % (sizeof(kPalette) / sizeof(kPalette[0]))];
}

void Draw(cairo_t* cr, const WorldDescription& world,
          const std::vector<TrajectoryTrace>& trajectories, double scale) {
  // World frame: x right, y up; one unit = one metre.
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  cairo_scale(cr, scale, -scale);
  cairo_translate(cr, -world.min_corner_m.x(), -world.max_corner_m.y());
  const double px = 1.0 / scale;  // one pixel in metres

  cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
  cairo_rectangle(cr, world.min_corner_m.x(), world.min_corner_m.y(),
                  world.max_corner_m.x() - world.min_corner_m.x(),
                  world.max_corner_m.y() - world.min_corner_m.y());
  cairo_fill(cr);

  for (const FaultSpec& fault : world.faults) {
    if (!fault.IsRegionFault()) continue;
    cairo_set_source_rgba(cr, 1.0, 0.1, 0.1, 0.25);
    cairo_rectangle(cr, fault.region_min_m.x(), fault.region_min_m.y(),
                    fault.region_max_m.x() - fault.region_min_m.x(),
                    fault.region_max_m.y() - fault.region_min_m.y());
    cairo_fill(cr);
  }
  for (const FloorStripe& stripe : world.stripes) {
    cairo_set_source_rgb(cr, 0.35, 0.35, 0.35);
    cairo_set_line_width(cr, std::max(stripe.width_m, 2 * px));
    cairo_move_to(cr, stripe.points_m[0].x(), stripe.points_m[0].y());
    for (const Eigen::Vector2d& p : stripe.points_m) cairo_line_to(cr, p.x(), p.y());
    cairo_stroke(cr);
  }
  for (const StripeMarker& marker : world.markers) {
    const Eigen::Vector2d half =
        0.5 * marker.length_m * Eigen::Vector2d(std::cos(marker.yaw_rad), std::sin(marker.yaw_rad));
    cairo_set_source_rgb(cr, 0.9, 0.75, 0.0);
    cairo_set_line_width(cr, std::max(0.05, 3 * px));
    cairo_move_to(cr, marker.position_m.x() - half.x(), marker.position_m.y() - half.y());
    cairo_line_to(cr, marker.position_m.x() + half.x(), marker.position_m.y() + half.y());
    cairo_stroke(cr);
  }
  for (const BoxObstacle& box : world.boxes) {
    const Rgb c = ColorOf(box.kind);
    cairo_save(cr);
    cairo_translate(cr, box.center_m.x(), box.center_m.y());
    cairo_rotate(cr, box.yaw_rad);
    cairo_set_source_rgb(cr, c.r, c.g, c.b);
    cairo_rectangle(cr, -0.5 * box.size_m.x(), -0.5 * box.size_m.y(), box.size_m.x(),
                    box.size_m.y());
    cairo_fill(cr);
    cairo_restore(cr);
  }
  for (const Trolley& trolley : world.trolleys) {
    cairo_save(cr);
    cairo_translate(cr, trolley.center_m.x(), trolley.center_m.y());
    cairo_rotate(cr, trolley.yaw_rad);
    cairo_set_source_rgba(cr, 0.8, 0.4, 0.0, 0.6);
    cairo_set_line_width(cr, 2 * px);
    cairo_rectangle(cr, -0.5 * trolley.size_m.x(), -0.5 * trolley.size_m.y(), trolley.size_m.x(),
                    trolley.size_m.y());
    cairo_stroke(cr);
    for (const Eigen::Vector2d& leg : trolley.LegsInTrolley()) {
      cairo_arc(cr, leg.x(), leg.y(), std::max(trolley.leg_radius_m, 2 * px), 0, 2 * M_PI);
      cairo_fill(cr);
    }
    cairo_restore(cr);
  }
  for (const CylinderObstacle& cylinder : world.cylinders) {
    const Rgb c = ColorOf(cylinder.kind);
    cairo_set_source_rgb(cr, c.r, c.g, c.b);
    cairo_arc(cr, cylinder.center_m.x(), cylinder.center_m.y(), std::max(cylinder.radius_m, 2 * px),
              0, 2 * M_PI);
    cairo_fill(cr);
  }
  for (const RobotSpawn& spawn : world.robots) {
    absl::StatusOr<RobotModel> model = RobotModelByKind(spawn.kind_name);
    if (!model.ok()) continue;
    cairo_set_source_rgba(cr, 0.85, 0.1, 0.1, 0.8);
    cairo_set_line_width(cr, 2 * px);
    for (size_t i = 0; i < model->footprint_m.size(); ++i) {
      const Eigen::Vector2d p = spawn.pose.TransformPoint(model->footprint_m[i]);
      if (i == 0) {
        cairo_move_to(cr, p.x(), p.y());
      } else {
        cairo_line_to(cr, p.x(), p.y());
      }
    }
    cairo_close_path(cr);
    cairo_stroke(cr);
  }
  std::map<std::string, size_t> colors;
  for (const TrajectoryTrace& trace : trajectories) {
    if (trace.points_m.size() < 2) continue;
    const size_t index = colors.emplace(trace.robot_id, colors.size()).first->second;
    const Rgb c = TrajectoryColor(index);
    cairo_set_source_rgb(cr, c.r, c.g, c.b);
    cairo_set_line_width(cr, 2.5 * px);
    if (trace.estimated) {
      const double dash[] = {6 * px, 4 * px};
      cairo_set_dash(cr, dash, 2, 0);
    } else {
      cairo_set_dash(cr, nullptr, 0, 0);
    }
    cairo_move_to(cr, trace.points_m[0].x(), trace.points_m[0].y());
    for (const Eigen::Vector2d& p : trace.points_m) cairo_line_to(cr, p.x(), p.y());
    cairo_stroke(cr);
  }
  cairo_set_dash(cr, nullptr, 0, 0);
}

bool EndsWith(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

absl::Status RenderWorld(const WorldDescription& world,
                         const std::vector<TrajectoryTrace>& trajectories, const std::string& path,
                         RenderParams params) {
  if (!(params.pixels_per_m > 0.0) || params.pixels_per_m > 1000.0) {
    return absl::InvalidArgumentError("pixels_per_m: must be in (0, 1000]");
  }
  WorldDescription framed = world;
  framed.min_corner_m -= Eigen::Vector2d::Constant(params.margin_m);
  framed.max_corner_m += Eigen::Vector2d::Constant(params.margin_m);
  const Eigen::Vector2d size = framed.max_corner_m - framed.min_corner_m;
  const int width = static_cast<int>(std::ceil(size.x() * params.pixels_per_m));
  const int height = static_cast<int>(std::ceil(size.y() * params.pixels_per_m));
  cairo_surface_t* surface = nullptr;
  const bool png = EndsWith(path, ".png");
  if (png) {
    surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
  } else if (EndsWith(path, ".svg")) {
    surface = cairo_svg_surface_create(path.c_str(), width, height);
  } else {
    return absl::InvalidArgumentError(
        absl::StrCat("render path '", path, "': must end in .png or .svg"));
  }
  cairo_t* cr = cairo_create(surface);
  // Draw the site as it is with its faults: a removed fence or stripe shows as a gap under its
  // (red) fault region.
  WorldDescription drawn = world;
  for (const FaultSpec& fault : world.faults) ApplyGeometryFault(fault, &drawn);
  drawn.min_corner_m = framed.min_corner_m;
  drawn.max_corner_m = framed.max_corner_m;
  Draw(cr, drawn, trajectories, params.pixels_per_m);
  cairo_destroy(cr);
  cairo_surface_flush(surface);
  cairo_status_t status = cairo_surface_status(surface);
  if (png && status == CAIRO_STATUS_SUCCESS) {
    status = cairo_surface_write_to_png(surface, path.c_str());
  }
  cairo_surface_finish(surface);
  if (status == CAIRO_STATUS_SUCCESS) status = cairo_surface_status(surface);
  cairo_surface_destroy(surface);
  if (status != CAIRO_STATUS_SUCCESS) {
    return absl::InternalError(
        absl::StrCat("render '", path, "': ", cairo_status_to_string(status)));
  }
  return absl::OkStatus();
}

absl::StatusOr<std::vector<TrajectoryTrace>> LoadTrajectoriesCsv(const std::string& path) {
  std::ifstream in(path);
  if (!in) return absl::NotFoundError(absl::StrCat("cannot open trajectory file '", path, "'"));
  std::vector<TrajectoryTrace> traces;
  std::map<std::pair<std::string, bool>, size_t> index;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line.rfind("robot_id", 0) == 0) continue;
    std::stringstream fields(line);
    std::string id, kind, x, y;
    if (!std::getline(fields, id, ',') || !std::getline(fields, kind, ',') ||
        !std::getline(fields, x, ',') || !std::getline(fields, y, ',') ||
        (kind != "truth" && kind != "estimate")) {
      return absl::InvalidArgumentError(
          absl::StrCat(path, ":", number, ": expected robot_id,truth|estimate,x,y"));
    }
    double px = 0, py = 0;
    try {
      px = std::stod(x);
      py = std::stod(y);
    } catch (const std::exception&) {
      return absl::InvalidArgumentError(absl::StrCat(path, ":", number, ": x, y must be numbers"));
    }
    const std::pair<std::string, bool> key{id, kind == "estimate"};
    auto it = index.find(key);
    if (it == index.end()) {
      it = index.emplace(key, traces.size()).first;
      traces.push_back({id, key.second, {}});
    }
    traces[it->second].points_m.emplace_back(px, py);
  }
  return traces;
}

}  // namespace fleetnav::sim
