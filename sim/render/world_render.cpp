#include "fleetnav/sim/world_render.hpp"

#include <cairo-svg.h>
#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/sim/render_style.hpp"

namespace fleetnav::sim {
namespace {

// Sizes of the annotations, in picture pixels.
constexpr double kPathWidthPx = 2.5;
constexpr double kCasingWidthPx = 5.0;  // the white line under every path
constexpr double kHaloWidthPx = 3.0;    // the white outline of path labels
constexpr double kStartDotRadiusPx = 3.5;
constexpr double kArrowLengthPx = 10.0;
constexpr double kLabelGapPx = 6.0;        // between a path end and its label
constexpr double kAwayFromEndPx = 12.0;    // how far back a path end's direction is taken
constexpr double kCornerInsetPx = 8.0;     // legend and scale bar from the picture's edges
constexpr double kBoxPaddingPx = 6.0;      // inside the scale bar's box
constexpr double kScaleBarHeightPx = 8.0;  // the bar with its end ticks
constexpr double kFooterItemGapPx = 12.0;  // between two line-style notes of the legend

Rgb ColorOf(const std::string& kind) {
  if (kind == "wall") return {0.15, 0.15, 0.15};
  if (kind == "fence") return {0.1, 0.6, 0.2};
  if (kind == "feed_kitchen") return {0.55, 0.35, 0.15};
  if (kind == "shelf") return {0.35, 0.45, 0.7};
  if (kind == "charging_pole") return {0.1, 0.3, 0.9};
  if (kind == "parcel") return {0.75, 0.6, 0.35};
  return {0.5, 0.5, 0.5};
}

void SetColor(cairo_t* cr, const Rgb& c, double alpha = 1.0) {
  cairo_set_source_rgba(cr, c.r, c.g, c.b, alpha);
}

void AddPolyline(cairo_t* cr, const std::vector<Eigen::Vector2d>& points) {
  cairo_move_to(cr, points[0].x(), points[0].y());
  for (const Eigen::Vector2d& p : points) cairo_line_to(cr, p.x(), p.y());
}

// World metres to picture pixels: x right, y down, origin at the framed world's top left.
struct PixelFrame {
  Eigen::Vector2d min_corner_m;
  Eigen::Vector2d max_corner_m;
  double pixels_per_m = 1.0;

  Eigen::Vector2d ToPx(const Eigen::Vector2d& p_m) const {
    return pixels_per_m * Eigen::Vector2d(p_m.x() - min_corner_m.x(), max_corner_m.y() - p_m.y());
  }
  Eigen::Vector2d SizePx() const { return pixels_per_m * (max_corner_m - min_corner_m); }
};

// The robots in colour order: those of the world first, then those only trajectories name.
std::vector<std::string> RobotOrder(const WorldDescription& world,
                                    const std::vector<TrajectoryTrace>& trajectories) {
  std::vector<std::string> order;
  std::set<std::string> seen;
  for (const RobotSpawn& spawn : world.robots) {
    if (seen.insert(spawn.robot_id).second) order.push_back(spawn.robot_id);
  }
  for (const TrajectoryTrace& trace : trajectories) {
    if (seen.insert(trace.robot_id).second) order.push_back(trace.robot_id);
  }
  return order;
}

// The floor and the red fault regions, in the world frame.
void DrawFloorAndFaults(cairo_t* cr, const WorldDescription& world) {
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
}

// Floor stripes and their markers, in the world frame; `px` is one pixel in metres.
void DrawStripesAndMarkers(cairo_t* cr, const WorldDescription& world, double px) {
  for (const FloorStripe& stripe : world.stripes) {
    cairo_set_source_rgb(cr, 0.35, 0.35, 0.35);
    cairo_set_line_width(cr, std::max(stripe.width_m, 2 * px));
    AddPolyline(cr, stripe.points_m);
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
}

// Boxes, trolleys and cylinders, in the world frame; `px` is one pixel in metres.
void DrawObstacles(cairo_t* cr, const WorldDescription& world, double px) {
  for (const BoxObstacle& box : world.boxes) {
    cairo_save(cr);
    cairo_translate(cr, box.center_m.x(), box.center_m.y());
    cairo_rotate(cr, box.yaw_rad);
    SetColor(cr, ColorOf(box.kind));
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
      cairo_arc(cr, leg.x(), leg.y(), std::max(trolley.leg_radius_m, 2 * px), 0, 2 * kPi);
      cairo_fill(cr);
    }
    cairo_restore(cr);
  }
  for (const CylinderObstacle& cylinder : world.cylinders) {
    SetColor(cr, ColorOf(cylinder.kind));
    cairo_arc(cr, cylinder.center_m.x(), cylinder.center_m.y(), std::max(cylinder.radius_m, 2 * px),
              0, 2 * kPi);
    cairo_fill(cr);
  }
}

// Every robot's footprint at its start pose in its colour, in the world frame.
void DrawStartFootprints(cairo_t* cr, const WorldDescription& world,
                         const std::map<std::string, Rgb>& colors, double px) {
  for (const RobotSpawn& spawn : world.robots) {
    absl::StatusOr<RobotModel> model = RobotModelByKind(spawn.kind_name);
    if (!model.ok() || model->footprint_m.empty()) continue;
    std::vector<Eigen::Vector2d> outline;
    for (const Eigen::Vector2d& p : model->footprint_m) {
      outline.push_back(spawn.pose.TransformPoint(p));
    }
    AddPolyline(cr, outline);
    cairo_close_path(cr);
    const Rgb& c = colors.at(spawn.robot_id);
    SetColor(cr, c, 0.25);
    cairo_fill_preserve(cr);
    SetColor(cr, c, 0.9);
    cairo_set_line_width(cr, 2 * px);
    cairo_stroke(cr);
  }
}

// The paths, in the world frame: first a white casing under all of them, so that they read
// over the map, then each in its robot's colour, truth solid and estimates dashed.
void DrawPaths(cairo_t* cr, const std::vector<TrajectoryTrace>& trajectories,
               const std::map<std::string, Rgb>& colors, double px) {
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  cairo_set_source_rgba(cr, 1.0, 1.0, 1.0, 0.8);
  cairo_set_line_width(cr, kCasingWidthPx * px);
  for (const TrajectoryTrace& trace : trajectories) {
    if (trace.points_m.size() < 2) continue;
    AddPolyline(cr, trace.points_m);
    cairo_stroke(cr);
  }
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
  cairo_set_line_width(cr, kPathWidthPx * px);
  for (const TrajectoryTrace& trace : trajectories) {
    if (trace.points_m.size() < 2) continue;
    SetColor(cr, colors.at(trace.robot_id));
    if (trace.estimated) {
      const double dash[] = {6 * px, 4 * px};
      cairo_set_dash(cr, dash, 2, 0);
    } else {
      cairo_set_dash(cr, nullptr, 0, 0);
    }
    AddPolyline(cr, trace.points_m);
    cairo_stroke(cr);
  }
  cairo_set_dash(cr, nullptr, 0, 0);
}

// The world and the paths, in the world frame (x right, y up; one unit = one metre).
void DrawWorldAndPaths(cairo_t* cr, const WorldDescription& world,
                       const std::vector<TrajectoryTrace>& trajectories,
                       const std::map<std::string, Rgb>& colors, double scale) {
  cairo_save(cr);
  cairo_scale(cr, scale, -scale);
  cairo_translate(cr, -world.min_corner_m.x(), -world.max_corner_m.y());
  const double px = 1.0 / scale;  // one pixel in metres
  DrawFloorAndFaults(cr, world);
  DrawStripesAndMarkers(cr, world, px);
  DrawObstacles(cr, world, px);
  DrawStartFootprints(cr, world, colors, px);
  DrawPaths(cr, trajectories, colors, px);
  cairo_restore(cr);
}

struct CairoDeleter {
  void operator()(cairo_t* cr) const { cairo_destroy(cr); }
  void operator()(cairo_surface_t* surface) const { cairo_surface_destroy(surface); }
};
using CairoPtr = std::unique_ptr<cairo_t, CairoDeleter>;
using SurfacePtr = std::unique_ptr<cairo_surface_t, CairoDeleter>;

// Selects the sans-serif face at `size_px`, with unhinted metrics so that text measured on one
// surface has the same size on another (PNG or SVG).
void SelectFont(cairo_t* cr, double size_px, bool bold) {
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size_px);
  cairo_font_options_t* options = cairo_font_options_create();
  cairo_font_options_set_hint_metrics(options, CAIRO_HINT_METRICS_OFF);
  cairo_set_font_options(cr, options);
  cairo_font_options_destroy(options);
}

// The size of `text` in the current font: its advance by the font's line height.
Eigen::Vector2d TextSizePx(cairo_t* cr, const std::string& text) {
  cairo_text_extents_t text_extents;
  cairo_text_extents(cr, text.c_str(), &text_extents);
  cairo_font_extents_t font_extents;
  cairo_font_extents(cr, &font_extents);
  return {text_extents.x_advance, font_extents.ascent + font_extents.descent};
}

// Adds `text` to the path with its left end at `left_x` and its line box centred on `center_y`.
void AddText(cairo_t* cr, const std::string& text, double left_x, double center_y) {
  cairo_font_extents_t font_extents;
  cairo_font_extents(cr, &font_extents);
  cairo_move_to(cr, left_x, center_y + 0.5 * (font_extents.ascent - font_extents.descent));
  cairo_text_path(cr, text.c_str());
}

// `text` centred on `center_px` in `color`, outlined in white so that it reads over the map.
void DrawHaloText(cairo_t* cr, const std::string& text, const Eigen::Vector2d& center_px,
                  const Rgb& color) {
  const Eigen::Vector2d size = TextSizePx(cr, text);
  AddText(cr, text, center_px.x() - 0.5 * size.x(), center_px.y());
  cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
  cairo_set_line_width(cr, kHaloWidthPx);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  cairo_stroke_preserve(cr);
  SetColor(cr, color);
  cairo_fill(cr);
}

void DrawBlackText(cairo_t* cr, const std::string& text, double left_x, double center_y) {
  AddText(cr, text, left_x, center_y);
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  cairo_fill(cr);
}

// A dot in `color` with a white rim: where a path starts.
void DrawStartDot(cairo_t* cr, const Eigen::Vector2d& at_px, const Rgb& color) {
  cairo_new_sub_path(cr);
  cairo_arc(cr, at_px.x(), at_px.y(), kStartDotRadiusPx, 0, 2 * kPi);
  SetColor(cr, color);
  cairo_fill_preserve(cr);
  cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
  cairo_set_line_width(cr, 1.2);
  cairo_stroke(cr);
}

// An arrowhead in `color` with a white rim, its tip a little beyond `at_px` along `heading`:
// where a path ends and which way it went.
void DrawEndArrow(cairo_t* cr, const Eigen::Vector2d& at_px, const Eigen::Vector2d& heading,
                  const Rgb& color) {
  const Eigen::Vector2d side = 0.45 * kArrowLengthPx * Eigen::Vector2d(-heading.y(), heading.x());
  const Eigen::Vector2d tip = at_px + 0.4 * kArrowLengthPx * heading;
  const Eigen::Vector2d base = tip - kArrowLengthPx * heading;
  cairo_move_to(cr, tip.x(), tip.y());
  cairo_line_to(cr, base.x() + side.x(), base.y() + side.y());
  cairo_line_to(cr, base.x() - side.x(), base.y() - side.y());
  cairo_close_path(cr);
  SetColor(cr, color);
  cairo_fill_preserve(cr);
  cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
  cairo_set_line_width(cr, 1.0);
  cairo_stroke(cr);
}

// A box with a white, slightly transparent fill and a grey rim, in device pixels.
void DrawPanel(cairo_t* cr, const Eigen::Vector2d& origin_px, const Eigen::Vector2d& size_px) {
  cairo_rectangle(cr, origin_px.x(), origin_px.y(), size_px.x(), size_px.y());
  cairo_set_source_rgba(cr, 1.0, 1.0, 1.0, 0.88);
  cairo_fill_preserve(cr);
  cairo_set_source_rgb(cr, 0.55, 0.55, 0.55);
  cairo_set_line_width(cr, 1.0);
  cairo_stroke(cr);
}

// One robot's path ends as drawn: a dot at the start, an arrowhead at the end, each labelled.
struct PathEnds {
  std::string robot_id;
  Eigen::Vector2d start_px;
  Eigen::Vector2d end_px;
  Eigen::Vector2d heading;  // out of the path at its end
  Eigen::Vector2d label_size_px;
  Eigen::Vector2d start_label_px;               // centre
  std::optional<Eigen::Vector2d> end_label_px;  // centre; none when it would cover the start's
};

// The path each robot's labels go on, in robot order: its truth, or its estimate when it has no
// truth.
std::vector<const TrajectoryTrace*> LabelledPaths(const std::vector<std::string>& order,
                                                  const std::vector<TrajectoryTrace>& traces) {
  std::map<std::string, const TrajectoryTrace*> chosen;
  for (const TrajectoryTrace& trace : traces) {
    if (trace.points_m.size() < 2) continue;
    const TrajectoryTrace*& slot = chosen[trace.robot_id];
    if (slot == nullptr || (slot->estimated && !trace.estimated)) slot = &trace;
  }
  std::vector<const TrajectoryTrace*> paths;
  for (const std::string& robot_id : order) {
    auto it = chosen.find(robot_id);
    if (it != chosen.end()) paths.push_back(it->second);
  }
  return paths;
}

// Where the end label of a path goes (its centre): beyond the end along the path, or beside it
// when that covers the start label (a path that comes back); nullopt when every place does.
std::optional<Eigen::Vector2d> EndLabelCenter(const Eigen::Vector2d& end_px,
                                              const Eigen::Vector2d& heading,
                                              const Eigen::Vector2d& size_px,
                                              const Eigen::Vector2d& start_center_px) {
  const Eigen::Vector2d side(-heading.y(), heading.x());
  for (const Eigen::Vector2d& away : {heading, side, Eigen::Vector2d(-side)}) {
    const Eigen::Vector2d center =
        LabelCenterPx(end_px, away, size_px, kLabelGapPx + 0.4 * kArrowLengthPx);
    if (!BoxesOverlap(center, size_px, start_center_px, size_px)) return center;
  }
  return std::nullopt;
}

// Places the ends of one path and their labels; `measure` holds the label font.
PathEnds PlacePathEnds(cairo_t* measure, const TrajectoryTrace& trace, const PixelFrame& frame) {
  std::vector<Eigen::Vector2d> points_px;
  points_px.reserve(trace.points_m.size());
  for (const Eigen::Vector2d& p : trace.points_m) points_px.push_back(frame.ToPx(p));
  PathEnds ends;
  ends.robot_id = trace.robot_id;
  ends.start_px = points_px.front();
  ends.end_px = points_px.back();
  ends.heading = AwayFromPath(points_px, /*at_start=*/false, kAwayFromEndPx);
  ends.label_size_px = TextSizePx(measure, trace.robot_id);
  ends.start_label_px =
      LabelCenterPx(ends.start_px, AwayFromPath(points_px, /*at_start=*/true, kAwayFromEndPx),
                    ends.label_size_px, kLabelGapPx);
  ends.end_label_px =
      EndLabelCenter(ends.end_px, ends.heading, ends.label_size_px, ends.start_label_px);
  return ends;
}

// The dots and arrowheads of all paths, then all their labels (no mark covers a label).
void DrawPathEnds(cairo_t* cr, const std::vector<PathEnds>& all_ends,
                  const std::map<std::string, Rgb>& colors, double font_size_px) {
  for (const PathEnds& ends : all_ends) {
    DrawStartDot(cr, ends.start_px, colors.at(ends.robot_id));
    DrawEndArrow(cr, ends.end_px, ends.heading, colors.at(ends.robot_id));
  }
  SelectFont(cr, font_size_px, /*bold=*/true);
  for (const PathEnds& ends : all_ends) {
    const Rgb& color = colors.at(ends.robot_id);
    DrawHaloText(cr, ends.robot_id, ends.start_label_px, color);
    if (ends.end_label_px) DrawHaloText(cr, ends.robot_id, *ends.end_label_px, color);
  }
}

// One note of the legend's footer: what a line, dot or arrowhead means.
enum class FooterSample { kTruth, kEstimate, kStart, kEnd };

struct FooterNote {
  FooterSample sample;
  std::string text;
};

// What the legend shows: the robots in colour order, then notes in rows on the line styles and
// the path ends.
struct LegendContent {
  std::vector<std::string> robot_ids;
  std::vector<std::vector<FooterNote>> footer_rows;
};

LegendContent MakeLegendContent(const std::vector<std::string>& order,
                                const std::vector<TrajectoryTrace>& trajectories,
                                bool path_labels) {
  LegendContent content;
  content.robot_ids = order;
  if (trajectories.empty()) return content;
  std::vector<FooterNote> lines = {{FooterSample::kTruth, "truth"}};
  if (std::any_of(trajectories.begin(), trajectories.end(),
                  [](const TrajectoryTrace& trace) { return trace.estimated; })) {
    lines.push_back({FooterSample::kEstimate, "estimate"});
  }
  content.footer_rows.push_back(lines);
  if (path_labels) {
    content.footer_rows.push_back({{FooterSample::kStart, "start"}, {FooterSample::kEnd, "end"}});
  }
  return content;
}

double FooterRowWidthPx(cairo_t* cr, const std::vector<FooterNote>& row, const LegendStyle& style) {
  double width_px = 0.0;
  for (const FooterNote& note : row) {
    if (width_px > 0.0) width_px += kFooterItemGapPx;
    width_px += style.swatch_width_px + style.swatch_gap_px + TextSizePx(cr, note.text).x();
  }
  return width_px;
}

// A line sample of the legend in `color`, solid or dashed.
void DrawLineSample(cairo_t* cr, double left_x, double center_y, double width_px, bool dashed,
                    const Rgb& color) {
  SetColor(cr, color);
  cairo_set_line_width(cr, kPathWidthPx + 0.5);
  const double dash[] = {6.0, 4.0};
  cairo_set_dash(cr, dashed ? dash : nullptr, dashed ? 2 : 0, 0);
  cairo_move_to(cr, left_x, center_y);
  cairo_line_to(cr, left_x + width_px, center_y);
  cairo_stroke(cr);
  cairo_set_dash(cr, nullptr, 0, 0);
}

void DrawFooterRow(cairo_t* cr, const std::vector<FooterNote>& row, double left_x, double center_y,
                   const LegendStyle& style) {
  const Rgb grey{0.3, 0.3, 0.3};
  double x = left_x;
  for (const FooterNote& note : row) {
    const Eigen::Vector2d middle(x + 0.5 * style.swatch_width_px, center_y);
    switch (note.sample) {
      case FooterSample::kTruth:
      case FooterSample::kEstimate:
        DrawLineSample(cr, x, center_y, style.swatch_width_px,
                       note.sample == FooterSample::kEstimate, grey);
        break;
      case FooterSample::kStart:
        DrawStartDot(cr, middle, grey);
        break;
      case FooterSample::kEnd:
        DrawEndArrow(cr, middle, Eigen::Vector2d(1.0, 0.0), grey);
        break;
    }
    x += style.swatch_width_px + style.swatch_gap_px;
    DrawBlackText(cr, note.text, x, center_y);
    x += TextSizePx(cr, note.text).x() + kFooterItemGapPx;
  }
}

// The legend as laid out and placed: in a corner of the map that it leaves every path and label
// free in, or else beside the map, right of it (`corner` empty).
struct LegendPlan {
  LegendContent content;
  LegendStyle style;
  LegendLayout layout;
  Eigen::Vector2d origin_px;
  std::optional<Corner> corner;
};

LegendPlan PlanLegend(cairo_t* measure, LegendContent content, const Eigen::Vector2d& map_px,
                      const std::vector<Eigen::Vector2d>& busy_px, double font_size_px) {
  LegendPlan plan;
  SelectFont(measure, font_size_px + 1.0, /*bold=*/false);
  double label_width_px = 0.0;
  for (const std::string& id : content.robot_ids) {
    label_width_px = std::max(label_width_px, TextSizePx(measure, id).x());
  }
  Eigen::Vector2d footer_px(0.0, plan.style.row_height_px * content.footer_rows.size());
  for (const std::vector<FooterNote>& row : content.footer_rows) {
    footer_px.x() = std::max(footer_px.x(), FooterRowWidthPx(measure, row, plan.style));
  }
  plan.layout = LayoutLegend(static_cast<int>(content.robot_ids.size()), label_width_px, footer_px,
                             map_px.x() - 2 * kCornerInsetPx, plan.style);
  plan.content = std::move(content);
  const Eigen::Vector2d box_px(plan.layout.width_px, plan.layout.height_px);
  const Corner corner = LeastCoveredCorner(
      map_px, box_px, kCornerInsetPx, busy_px,
      {Corner::kTopRight, Corner::kTopLeft, Corner::kBottomRight, Corner::kBottomLeft});
  const Eigen::Vector2d origin = BoxOriginPx(corner, map_px, box_px, kCornerInsetPx);
  const bool fits = (box_px.array() <= map_px.array() - 2 * kCornerInsetPx).all();
  if (fits && PointsInBox(origin, box_px, busy_px) == 0) {
    plan.corner = corner;
    plan.origin_px = origin;
  } else {
    plan.origin_px = Eigen::Vector2d(map_px.x() + kCornerInsetPx, kCornerInsetPx);
  }
  return plan;
}

void DrawLegend(cairo_t* cr, const LegendPlan& plan, const std::map<std::string, Rgb>& colors,
                double font_size_px) {
  const LegendStyle& style = plan.style;
  SelectFont(cr, font_size_px + 1.0, /*bold=*/false);
  DrawPanel(cr, plan.origin_px, Eigen::Vector2d(plan.layout.width_px, plan.layout.height_px));
  for (size_t i = 0; i < plan.content.robot_ids.size(); ++i) {
    const Eigen::Vector2d at =
        plan.origin_px + plan.layout.EntryOffsetPx(static_cast<int>(i), style);
    const double center_y = at.y() + 0.5 * style.row_height_px;
    const std::string& id = plan.content.robot_ids[i];
    DrawLineSample(cr, at.x(), center_y, style.swatch_width_px, false, colors.at(id));
    DrawBlackText(cr, id, at.x() + style.swatch_width_px + style.swatch_gap_px, center_y);
  }
  for (size_t r = 0; r < plan.content.footer_rows.size(); ++r) {
    const double center_y =
        plan.origin_px.y() + plan.layout.footer_top_px + (r + 0.5) * style.row_height_px;
    DrawFooterRow(cr, plan.content.footer_rows[r], plan.origin_px.x() + style.padding_px, center_y,
                  style);
  }
}

// A bar of a round length (ScaleBarLengthM of the map's width) with end ticks and its length
// above it, in the bottom corner of the map, other than `taken`, that covers the fewest paths.
void DrawScaleBar(cairo_t* cr, const PixelFrame& frame, const Eigen::Vector2d& map_px,
                  std::optional<Corner> taken, const std::vector<Eigen::Vector2d>& busy_px,
                  double font_size_px) {
  const double length_m = ScaleBarLengthM(frame.max_corner_m.x() - frame.min_corner_m.x());
  const double length_px = length_m * frame.pixels_per_m;
  const std::string label = ScaleBarLabel(length_m);
  SelectFont(cr, font_size_px + 1.0, /*bold=*/false);
  const Eigen::Vector2d text_px = TextSizePx(cr, label);
  const Eigen::Vector2d box_px(std::max(length_px, text_px.x()) + 2 * kBoxPaddingPx,
                               text_px.y() + kScaleBarHeightPx + 2 * kBoxPaddingPx + 2.0);
  std::vector<Corner> candidates;
  for (Corner corner : {Corner::kBottomLeft, Corner::kBottomRight}) {
    if (corner != taken) candidates.push_back(corner);
  }
  const Corner corner = LeastCoveredCorner(map_px, box_px, kCornerInsetPx, busy_px, candidates);
  const Eigen::Vector2d origin = BoxOriginPx(corner, map_px, box_px, kCornerInsetPx);
  DrawPanel(cr, origin, box_px);
  const double left_x = origin.x() + 0.5 * (box_px.x() - length_px);
  const double bar_y = origin.y() + box_px.y() - kBoxPaddingPx - 0.5 * kScaleBarHeightPx;
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  cairo_set_line_width(cr, 3.0);
  cairo_move_to(cr, left_x, bar_y);
  cairo_line_to(cr, left_x + length_px, bar_y);
  cairo_stroke(cr);
  cairo_set_line_width(cr, 1.5);
  for (double x : {left_x, left_x + length_px}) {
    cairo_move_to(cr, x, bar_y - 0.5 * kScaleBarHeightPx);
    cairo_line_to(cr, x, bar_y + 0.5 * kScaleBarHeightPx);
  }
  cairo_stroke(cr);
  DrawBlackText(cr, label, origin.x() + 0.5 * (box_px.x() - text_px.x()),
                origin.y() + kBoxPaddingPx + 0.5 * text_px.y());
}

// What the legend and the scale bar should leave free, in device pixels: the paths (a point
// every few pixels), the robots' starts and the corners and centres of the path labels.
std::vector<Eigen::Vector2d> BusyPointsPx(const WorldDescription& world,
                                          const std::vector<TrajectoryTrace>& trajectories,
                                          const std::vector<PathEnds>& all_ends,
                                          const PixelFrame& frame) {
  constexpr double kStepPx = 4.0;
  std::vector<Eigen::Vector2d> points;
  for (const RobotSpawn& spawn : world.robots) {
    points.push_back(frame.ToPx(spawn.pose.translation()));
  }
  for (const TrajectoryTrace& trace : trajectories) {
    for (size_t i = 0; i < trace.points_m.size(); ++i) {
      const Eigen::Vector2d to = frame.ToPx(trace.points_m[i]);
      const Eigen::Vector2d from = i > 0 ? frame.ToPx(trace.points_m[i - 1]) : to;
      const double length_px = (to - from).norm();
      const int steps = std::isfinite(length_px)
                            ? static_cast<int>(std::min(std::ceil(length_px / kStepPx), 1e5))
                            : 0;
      for (int k = 1; k < steps; ++k) points.push_back(from + (to - from) * k / steps);
      points.push_back(to);
    }
  }
  for (const PathEnds& ends : all_ends) {
    std::vector<Eigen::Vector2d> centers = {ends.start_label_px};
    if (ends.end_label_px) centers.push_back(*ends.end_label_px);
    for (const Eigen::Vector2d& center : centers) {
      points.push_back(center);
      for (double sx : {-0.5, 0.5}) {
        for (double sy : {-0.5, 0.5}) {
          points.push_back(center + ends.label_size_px.cwiseProduct(Eigen::Vector2d(sx, sy)));
        }
      }
    }
  }
  return points;
}

// Everything decided before drawing: the robots' colours, the path ends and their labels, the
// legend, and so the picture's size.
struct PicturePlan {
  PixelFrame frame;
  Eigen::Vector2d map_px;  // the framed world, whole pixels
  int width_px = 0;        // the map and the legend when it stands beside
  int height_px = 0;
  std::map<std::string, Rgb> colors;
  std::vector<PathEnds> path_ends;
  std::vector<Eigen::Vector2d> busy_px;
  std::optional<LegendPlan> legend;
};

// Plans the picture of `world` (already framed: its corners are the picture's).
PicturePlan PlanPicture(const WorldDescription& world,
                        const std::vector<TrajectoryTrace>& trajectories,
                        const RenderParams& params) {
  PicturePlan plan;
  plan.frame = PixelFrame{world.min_corner_m, world.max_corner_m, params.pixels_per_m};
  plan.map_px = plan.frame.SizePx().array().ceil().matrix();
  const std::vector<std::string> order = RobotOrder(world, trajectories);
  const std::vector<Rgb> palette = RobotColors(order.size());
  for (size_t i = 0; i < order.size(); ++i) plan.colors[order[i]] = palette[i];
  // Text is measured on a scratch surface: the picture's size depends on the legend's.
  const SurfacePtr scratch(cairo_image_surface_create(CAIRO_FORMAT_RGB24, 1, 1));
  const CairoPtr measure(cairo_create(scratch.get()));
  if (params.path_labels) {
    SelectFont(measure.get(), params.font_size_px, /*bold=*/true);
    for (const TrajectoryTrace* trace : LabelledPaths(order, trajectories)) {
      plan.path_ends.push_back(PlacePathEnds(measure.get(), *trace, plan.frame));
    }
  }
  plan.busy_px = BusyPointsPx(world, trajectories, plan.path_ends, plan.frame);
  LegendContent content = MakeLegendContent(order, trajectories, params.path_labels);
  if (params.legend && (!content.robot_ids.empty() || !content.footer_rows.empty())) {
    plan.legend = PlanLegend(measure.get(), std::move(content), plan.map_px, plan.busy_px,
                             params.font_size_px);
  }
  Eigen::Vector2d picture_px = plan.map_px;
  if (plan.legend && !plan.legend->corner) {
    const Eigen::Vector2d beside_px =
        plan.legend->origin_px +
        Eigen::Vector2d(plan.legend->layout.width_px, plan.legend->layout.height_px) +
        Eigen::Vector2d::Constant(kCornerInsetPx);
    picture_px = picture_px.cwiseMax(beside_px.array().ceil().matrix());
  }
  plan.width_px = static_cast<int>(picture_px.x());
  plan.height_px = static_cast<int>(picture_px.y());
  return plan;
}

void Draw(cairo_t* cr, const WorldDescription& world,
          const std::vector<TrajectoryTrace>& trajectories, const PicturePlan& plan,
          const RenderParams& params) {
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  DrawWorldAndPaths(cr, world, trajectories, plan.colors, params.pixels_per_m);
  // Annotations, in device pixels.
  DrawPathEnds(cr, plan.path_ends, plan.colors, params.font_size_px);
  std::optional<Corner> legend_corner;
  if (plan.legend) {
    DrawLegend(cr, *plan.legend, plan.colors, params.font_size_px);
    legend_corner = plan.legend->corner;
  }
  if (params.scale_bar) {
    DrawScaleBar(cr, plan.frame, plan.map_px, legend_corner, plan.busy_px, params.font_size_px);
  }
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
  if (!(params.font_size_px >= 4.0) || params.font_size_px > 100.0) {
    return absl::InvalidArgumentError("font_size_px: must be in [4, 100]");
  }
  const bool png = EndsWith(path, ".png");
  if (!png && !EndsWith(path, ".svg")) {
    return absl::InvalidArgumentError(
        absl::StrCat("render path '", path, "': must end in .png or .svg"));
  }
  // Draw the site as it is with its faults: a removed fence or stripe shows as a gap under its
  // (red) fault region.
  WorldDescription drawn = world;
  for (const FaultSpec& fault : world.faults) ApplyGeometryFault(fault, &drawn);
  drawn.min_corner_m = world.min_corner_m - Eigen::Vector2d::Constant(params.margin_m);
  drawn.max_corner_m = world.max_corner_m + Eigen::Vector2d::Constant(params.margin_m);
  const PicturePlan plan = PlanPicture(drawn, trajectories, params);
  cairo_surface_t* surface =
      png ? cairo_image_surface_create(CAIRO_FORMAT_RGB24, plan.width_px, plan.height_px)
          : cairo_svg_surface_create(path.c_str(), plan.width_px, plan.height_px);
  cairo_t* cr = cairo_create(surface);
  Draw(cr, drawn, trajectories, plan, params);
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
