#include "fleetnav/sim/render_style.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "absl/strings/str_format.h"

namespace fleetnav::sim {
namespace {

constexpr Rgb Hex(uint32_t rgb) {
  return {((rgb >> 16) & 0xff) / 255.0, ((rgb >> 8) & 0xff) / 255.0, (rgb & 0xff) / 255.0};
}

// Tableau 10 without its grey (cyan and olive darkened to read on white), then navy, maroon and
// violet red: pairwise more than 27 apart in DeltaE76.
constexpr std::array<Rgb, 12> kFixedPalette = {
    Hex(0x1f77b4), Hex(0xd62728), Hex(0x2ca02c), Hex(0xff7f0e), Hex(0x9467bd), Hex(0x8c564b),
    Hex(0xe377c2), Hex(0x1399a8), Hex(0x9c9c18), Hex(0x000080), Hex(0x800000), Hex(0xc71585)};

// Colours of the map that a robot colour keeps away from: white, the floor, mid grey, walls.
constexpr std::array<Rgb, 4> kMapColors = {Rgb{1.0, 1.0, 1.0}, Rgb{0.9, 0.9, 0.9},
                                           Rgb{0.5, 0.5, 0.5}, Rgb{0.15, 0.15, 0.15}};

// The candidate grid of the sampled colours: hue every 5 degrees, HSL lightness and saturation.
constexpr int kHueSteps = 72;
constexpr std::array<double, 4> kLightness = {0.25, 0.35, 0.45, 0.55};
constexpr std::array<double, 3> kSaturation = {0.55, 0.75, 0.95};
constexpr double kMinCieLightness = 25.0;
constexpr double kMaxCieLightness = 68.0;

double SrgbToLinear(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

double LabF(double t) {
  constexpr double kEpsilon = 216.0 / 24389.0;
  constexpr double kKappa = 24389.0 / 27.0;
  return t > kEpsilon ? std::cbrt(t) : (kKappa * t + 16.0) / 116.0;
}

// CIELAB (L*, a*, b*) of an sRGB colour, D65 white.
Eigen::Vector3d Lab(const Rgb& c) {
  const double r = SrgbToLinear(c.r);
  const double g = SrgbToLinear(c.g);
  const double b = SrgbToLinear(c.b);
  const double x = (0.4124 * r + 0.3576 * g + 0.1805 * b) / 0.95047;
  const double y = 0.2126 * r + 0.7152 * g + 0.0722 * b;
  const double z = (0.0193 * r + 0.1192 * g + 0.9505 * b) / 1.08883;
  const double fx = LabF(x);
  const double fy = LabF(y);
  const double fz = LabF(z);
  return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

double HueToChannel(double p, double q, double t) {
  if (t < 0.0) t += 1.0;
  if (t > 1.0) t -= 1.0;
  if (t < 1.0 / 6.0) return p + (q - p) * 6.0 * t;
  if (t < 0.5) return q;
  if (t < 2.0 / 3.0) return p + (q - p) * (2.0 / 3.0 - t) * 6.0;
  return p;
}

// HSL to sRGB, each of hue (in turns), saturation and lightness in [0, 1].
Rgb FromHsl(double hue, double saturation, double lightness) {
  const double q = lightness < 0.5 ? lightness * (1.0 + saturation)
                                   : lightness + saturation - lightness * saturation;
  const double p = 2.0 * lightness - q;
  return {HueToChannel(p, q, hue + 1.0 / 3.0), HueToChannel(p, q, hue),
          HueToChannel(p, q, hue - 1.0 / 3.0)};
}

std::vector<Rgb> CandidateColors() {
  std::vector<Rgb> candidates;
  for (int h = 0; h < kHueSteps; ++h) {
    for (double lightness : kLightness) {
      for (double saturation : kSaturation) {
        const Rgb c = FromHsl(static_cast<double>(h) / kHueSteps, saturation, lightness);
        const double cie_lightness = Lab(c).x();
        if (cie_lightness >= kMinCieLightness && cie_lightness <= kMaxCieLightness) {
          candidates.push_back(c);
        }
      }
    }
  }
  return candidates;
}

// Appends colours to `colors` until it holds `count`: each the candidate farthest from all
// colours taken so far and from the map's colours (farthest-point sampling; the first of equals).
void AppendFarthestColors(size_t count, std::vector<Rgb>* colors) {
  const std::vector<Rgb> candidates = CandidateColors();
  std::vector<Eigen::Vector3d> lab(candidates.size());
  std::vector<double> nearest(candidates.size(), std::numeric_limits<double>::infinity());
  auto take = [&](const Rgb& taken) {
    const Eigen::Vector3d taken_lab = Lab(taken);
    for (size_t i = 0; i < candidates.size(); ++i) {
      nearest[i] = std::min(nearest[i], (lab[i] - taken_lab).norm());
    }
  };
  for (size_t i = 0; i < candidates.size(); ++i) lab[i] = Lab(candidates[i]);
  for (const Rgb& c : kMapColors) take(c);
  for (const Rgb& c : *colors) take(c);
  while (colors->size() < count) {
    const size_t best =
        static_cast<size_t>(std::max_element(nearest.begin(), nearest.end()) - nearest.begin());
    colors->push_back(candidates[best]);
    take(candidates[best]);
  }
}

}  // namespace

double DeltaE76(const Rgb& a, const Rgb& b) { return (Lab(a) - Lab(b)).norm(); }

double RgbDistance(const Rgb& a, const Rgb& b) {
  return Eigen::Vector3d(a.r - b.r, a.g - b.g, a.b - b.b).norm();
}

std::vector<Rgb> RobotColors(size_t count) {
  std::vector<Rgb> colors;
  colors.reserve(count);
  for (const Rgb& c : kFixedPalette) {
    if (colors.size() == count) return colors;
    colors.push_back(c);
  }
  if (colors.size() < count) AppendFarthestColors(count, &colors);
  return colors;
}

double ScaleBarLengthM(double picture_width_m, double target_fraction) {
  const double target_m = picture_width_m * target_fraction;
  if (!std::isfinite(target_m) || target_m <= 0.0) return 1.0;
  const int exponent = static_cast<int>(std::floor(std::log10(target_m)));
  double best_m = 1.0;
  double best_error = std::numeric_limits<double>::infinity();
  for (int e = exponent - 1; e <= exponent + 1; ++e) {
    // 10^e without the rounding of a negative power: 0.5 is 5 / 10, not 5 * 0.1.
    const double decade = std::pow(10.0, std::abs(e));
    for (double mantissa : {1.0, 2.0, 5.0}) {
      const double length_m = e >= 0 ? mantissa * decade : mantissa / decade;
      const double error = std::abs(std::log(length_m / target_m));
      if (error < best_error) {
        best_error = error;
        best_m = length_m;
      }
    }
  }
  return best_m;
}

std::string ScaleBarLabel(double length_m) { return absl::StrFormat("%g m", length_m); }

Eigen::Vector2d LegendLayout::EntryOffsetPx(int index, const LegendStyle& style) const {
  const int column = rows > 0 ? index / rows : 0;
  const int row = rows > 0 ? index % rows : 0;
  return {style.padding_px + column * (column_width_px + style.column_gap_px),
          style.padding_px + row * style.row_height_px};
}

LegendLayout LayoutLegend(int entries, double max_label_width_px,
                          const Eigen::Vector2d& footer_size_px, double max_width_px,
                          const LegendStyle& style) {
  LegendLayout layout;
  entries = std::max(entries, 0);
  if (entries == 0 && footer_size_px.x() <= 0.0 && footer_size_px.y() <= 0.0) return layout;
  layout.column_width_px = style.swatch_width_px + style.swatch_gap_px + max_label_width_px;
  auto width_of = [&](int columns) {
    const double body =
        columns > 0 ? columns * layout.column_width_px + (columns - 1) * style.column_gap_px : 0.0;
    return 2.0 * style.padding_px + std::max(body, footer_size_px.x());
  };
  const int max_rows = std::max(style.max_rows, 1);
  int columns = (entries + max_rows - 1) / max_rows;
  while (columns > 1 && width_of(columns) > max_width_px) --columns;
  layout.rows = columns > 0 ? (entries + columns - 1) / columns : 0;
  // Balanced: as few columns as the rows need (11 robots in rows of 6: 2 columns, not 3).
  layout.columns = layout.rows > 0 ? (entries + layout.rows - 1) / layout.rows : 0;
  layout.width_px = width_of(layout.columns);
  layout.footer_top_px = style.padding_px + layout.rows * style.row_height_px;
  layout.height_px = layout.footer_top_px + footer_size_px.y() + style.padding_px;
  return layout;
}

Eigen::Vector2d BoxOriginPx(Corner corner, const Eigen::Vector2d& picture_size_px,
                            const Eigen::Vector2d& box_size_px, double inset_px) {
  const double left = inset_px;
  const double right = picture_size_px.x() - inset_px - box_size_px.x();
  const double top = inset_px;
  const double bottom = picture_size_px.y() - inset_px - box_size_px.y();
  switch (corner) {
    case Corner::kTopRight:
      return {right, top};
    case Corner::kTopLeft:
      return {left, top};
    case Corner::kBottomRight:
      return {right, bottom};
    case Corner::kBottomLeft:
      return {left, bottom};
  }
  return {left, top};
}

size_t PointsInBox(const Eigen::Vector2d& origin_px, const Eigen::Vector2d& box_size_px,
                   const std::vector<Eigen::Vector2d>& points_px) {
  const Eigen::Vector2d max = origin_px + box_size_px;
  return static_cast<size_t>(
      std::count_if(points_px.begin(), points_px.end(), [&](const Eigen::Vector2d& p) {
        return p.x() >= origin_px.x() && p.x() <= max.x() && p.y() >= origin_px.y() &&
               p.y() <= max.y();
      }));
}

Corner LeastCoveredCorner(const Eigen::Vector2d& picture_size_px,
                          const Eigen::Vector2d& box_size_px, double inset_px,
                          const std::vector<Eigen::Vector2d>& points_px,
                          const std::vector<Corner>& candidates) {
  Corner best = Corner::kTopRight;
  size_t best_covered = std::numeric_limits<size_t>::max();
  for (Corner corner : candidates) {
    const size_t covered = PointsInBox(BoxOriginPx(corner, picture_size_px, box_size_px, inset_px),
                                       box_size_px, points_px);
    if (covered < best_covered) {
      best_covered = covered;
      best = corner;
    }
  }
  return best;
}

Eigen::Vector2d AwayFromPath(const std::vector<Eigen::Vector2d>& points, bool at_start,
                             double min_distance) {
  const Eigen::Vector2d up_right = Eigen::Vector2d(1.0, -1.0).normalized();
  if (points.empty()) return up_right;
  const size_t n = points.size();
  const Eigen::Vector2d& end = at_start ? points.front() : points.back();
  Eigen::Vector2d farthest = end;
  double farthest_distance = 0.0;
  for (size_t k = 1; k < n; ++k) {
    const Eigen::Vector2d& p = at_start ? points[k] : points[n - 1 - k];
    const double distance = (p - end).norm();
    if (distance >= min_distance && distance > 0.0) return (end - p) / distance;
    if (distance > farthest_distance) {
      farthest_distance = distance;
      farthest = p;
    }
  }
  return farthest_distance > 0.0 ? Eigen::Vector2d((end - farthest) / farthest_distance) : up_right;
}

Eigen::Vector2d LabelCenterPx(const Eigen::Vector2d& end_px, const Eigen::Vector2d& away,
                              const Eigen::Vector2d& text_size_px, double gap_px) {
  const double largest = std::max(std::abs(away.x()), std::abs(away.y()));
  const Eigen::Vector2d unit =
      largest > 0.0 ? Eigen::Vector2d(away.normalized()) : Eigen::Vector2d(1.0, 0.0);
  // `unit` scaled onto the square [-1, 1]^2: the box's near edge or corner is at the gap.
  const Eigen::Vector2d on_square = unit / std::max(std::abs(unit.x()), std::abs(unit.y()));
  return end_px + gap_px * unit + 0.5 * on_square.cwiseProduct(text_size_px);
}

bool BoxesOverlap(const Eigen::Vector2d& center_a, const Eigen::Vector2d& size_a,
                  const Eigen::Vector2d& center_b, const Eigen::Vector2d& size_b) {
  const Eigen::Vector2d gap = (center_a - center_b).cwiseAbs() - 0.5 * (size_a + size_b);
  return gap.x() < 0.0 && gap.y() < 0.0;
}

}  // namespace fleetnav::sim
