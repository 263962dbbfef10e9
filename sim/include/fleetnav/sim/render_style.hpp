#pragma once

// Pure layout and colour helpers of the world pictures (world_render.hpp), kept apart from
// cairo so that they can be tested without drawing. Lengths in pixels are in the picture's
// device frame: x right, y down, origin at the top-left corner.

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

namespace fleetnav::sim {

/// An sRGB colour, each channel in [0, 1].
struct Rgb {
  double r = 0.0;
  double g = 0.0;
  double b = 0.0;
};

/// CIE76 colour difference of two sRGB colours (CIELAB, D65 white): about 2.3 is just
/// noticeable, above 10 two line colours are told apart at a glance.
double DeltaE76(const Rgb& a, const Rgb& b);

/// Euclidean distance of two colours in RGB, channels in [0, 1] (at most sqrt(3)).
double RgbDistance(const Rgb& a, const Rgb& b);

/// `count` robot colours in robot order: first a fixed qualitative palette of 12 (Tableau 10
/// without its grey, two of its light colours darkened, and navy, maroon, violet red), then
/// farthest-point sampling in CIELAB: each next colour is, of a fixed grid of HSL candidates
/// with CIE L* in [25, 68] (dark enough for a thin line on white), the one farthest from every
/// colour taken so far and from the map's white, greys and wall black. Deterministic and
/// prefix-stable (the first n colours of RobotColors(m) are RobotColors(n)); the 50 first are
/// pairwise more than 15 apart in DeltaE76. Past the ~620 colours of the grid, colours repeat.
std::vector<Rgb> RobotColors(size_t count);

/// The length of a scale bar for a picture `picture_width_m` wide: the 1-2-5 number
/// (..., 0.5, 1, 2, 5, 10, 20, ... m) closest, on a log scale, to `target_fraction` of the width.
/// With the default 0.2 it lies within 15-25 % of the width whenever a 1-2-5 number does,
/// and always within a factor 1.6 of 20 %. 1 m for a width that is not positive and finite.
double ScaleBarLengthM(double picture_width_m, double target_fraction = 0.2);

/// The label of a scale bar: "5 m", "0.5 m", "20 m".
std::string ScaleBarLabel(double length_m);

/// Sizes of the legend box, in pixels.
struct LegendStyle {
  double row_height_px = 16.0;    ///< one robot per row
  double padding_px = 6.0;        ///< inside the box, around its content
  double swatch_width_px = 22.0;  ///< the coloured line sample before each robot id
  double swatch_gap_px = 5.0;     ///< between the sample and the id
  double column_gap_px = 14.0;    ///< between two columns
  int max_rows = 10;              ///< rows per column before another column starts
};

/// Where the legend's entries go: `rows` x `columns` robot entries filled column by column,
/// then a footer (line styles) across the box. Offsets are from the box's top-left corner.
struct LegendLayout {
  int rows = 0;
  int columns = 0;
  double column_width_px = 0.0;
  double width_px = 0.0;
  double height_px = 0.0;
  double footer_top_px = 0.0;  ///< the footer's top edge

  /// The top-left corner of entry `index` (0 <= index < rows * columns).
  Eigen::Vector2d EntryOffsetPx(int index, const LegendStyle& style) const;
};

/// Lays out a legend of `entries` robots whose longest id is `max_label_width_px` wide, above a
/// footer `footer_size_px` (width, height; zero for none): columns of at most style.max_rows,
/// balanced (12 robots: 2 x 6), and fewer, longer columns while the box is wider than
/// `max_width_px`. A box that cannot fit the picture at all is still laid out (it then covers
/// part of the map). Zero entries and no footer: an empty layout (no box).
LegendLayout LayoutLegend(int entries, double max_label_width_px,
                          const Eigen::Vector2d& footer_size_px, double max_width_px,
                          const LegendStyle& style = {});

/// A corner of the picture.
enum class Corner { kTopRight, kTopLeft, kBottomRight, kBottomLeft };

/// The top-left position of a box of `box_size_px` in `corner` of a picture of `picture_size_px`,
/// `inset_px` from its edges.
Eigen::Vector2d BoxOriginPx(Corner corner, const Eigen::Vector2d& picture_size_px,
                            const Eigen::Vector2d& box_size_px, double inset_px);

/// How many of `points_px` lie in the box of `box_size_px` whose top-left corner is at
/// `origin_px` (its edges included).
size_t PointsInBox(const Eigen::Vector2d& origin_px, const Eigen::Vector2d& box_size_px,
                   const std::vector<Eigen::Vector2d>& points_px);

/// The corner, of `candidates`, where a box of `box_size_px` covers the fewest of `points_px`
/// (the drawn paths); of equals, the one earliest in `candidates`. Top right when `candidates`
/// is empty.
Corner LeastCoveredCorner(const Eigen::Vector2d& picture_size_px,
                          const Eigen::Vector2d& box_size_px, double inset_px,
                          const std::vector<Eigen::Vector2d>& points_px,
                          const std::vector<Corner>& candidates);

/// The unit direction pointing out of a path at its start (`at_start`) or its end: from the
/// first point at least `min_distance` from that end, walking along the path, towards the end
/// point (from the farthest point when none is that far; up-right, (1, -1)/sqrt(2) in device
/// pixels, when all points coincide or there are none).
Eigen::Vector2d AwayFromPath(const std::vector<Eigen::Vector2d>& points, bool at_start,
                             double min_distance);

/// The centre of a text box of `text_size_px` labelling a path end at `end_px`: the box sits
/// `gap_px` beyond the end along the unit direction `away`, touching that point with its nearest
/// edge or corner, so that it does not cover the end of the path.
Eigen::Vector2d LabelCenterPx(const Eigen::Vector2d& end_px, const Eigen::Vector2d& away,
                              const Eigen::Vector2d& text_size_px, double gap_px);

/// Whether two axis-aligned boxes, given by centre and size, overlap.
bool BoxesOverlap(const Eigen::Vector2d& center_a, const Eigen::Vector2d& size_a,
                  const Eigen::Vector2d& center_b, const Eigen::Vector2d& size_b);

}  // namespace fleetnav::sim
