// Colours, scale bar, legend layout and label placement of the world pictures, and a picture of
// twelve robots read back pixel by pixel.
#include "fleetnav/sim/render_style.hpp"

#include <cairo.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "absl/strings/str_format.h"
#include "fleetnav/sim/world_render.hpp"

namespace fleetnav::sim {
namespace {

bool IsOneTwoFive(double length_m) {
  const double mantissa = length_m / std::pow(10.0, std::floor(std::log10(length_m) + 1e-12));
  for (double m : {1.0, 2.0, 5.0}) {
    if (std::abs(mantissa - m) < 1e-9) return true;
  }
  return false;
}

// Whether some 1-2-5 length lies within [0.15, 0.25] of `width_m`.
bool SomeOneTwoFiveFits(double width_m) {
  for (int e = -6; e <= 6; ++e) {
    for (double m : {1.0, 2.0, 5.0}) {
      const double length_m = m * std::pow(10.0, e);
      if (length_m >= 0.15 * width_m && length_m <= 0.25 * width_m) return true;
    }
  }
  return false;
}

TEST(RobotColorsTest, FiftyColoursArePairwiseDistinct) {
  const std::vector<Rgb> colors = RobotColors(50);
  ASSERT_EQ(colors.size(), 50u);
  for (size_t i = 0; i < colors.size(); ++i) {
    for (size_t j = i + 1; j < colors.size(); ++j) {
      EXPECT_GT(RgbDistance(colors[i], colors[j]), 0.1) << i << " " << j;
      EXPECT_GT(DeltaE76(colors[i], colors[j]), 15.0) << i << " " << j;
    }
  }
}

TEST(RobotColorsTest, DeterministicAndPrefixStable) {
  const std::vector<Rgb> fifty = RobotColors(50);
  const std::vector<Rgb> again = RobotColors(50);
  EXPECT_TRUE(RobotColors(0).empty());
  for (size_t count : {1u, 5u, 12u, 13u, 20u, 50u}) {
    const std::vector<Rgb> some = RobotColors(count);
    ASSERT_EQ(some.size(), count);
    for (size_t i = 0; i < count; ++i) {
      EXPECT_EQ(some[i].r, fifty[i].r) << count << " " << i;
      EXPECT_EQ(some[i].g, fifty[i].g) << count << " " << i;
      EXPECT_EQ(some[i].b, fifty[i].b) << count << " " << i;
    }
  }
  for (size_t i = 0; i < fifty.size(); ++i) EXPECT_EQ(RgbDistance(fifty[i], again[i]), 0.0);
}

TEST(RobotColorsTest, EveryColourReadsOnWhiteAndIsNoGrey) {
  const Rgb white{1.0, 1.0, 1.0};
  for (const Rgb& c : RobotColors(100)) {
    for (double channel : {c.r, c.g, c.b}) {
      EXPECT_GE(channel, 0.0);
      EXPECT_LE(channel, 1.0);
    }
    EXPECT_GT(DeltaE76(c, white), 30.0);
    EXPECT_GT(DeltaE76(c, Rgb{0.5, 0.5, 0.5}), 10.0);
  }
}

TEST(ScaleBarTest, IsOneTwoFiveWithinFifteenToTwentyFivePercent) {
  for (double width_m : {0.6, 1.3, 4.0, 10.0, 27.0, 41.0, 60.0, 100.0, 250.0, 1000.0}) {
    const double length_m = ScaleBarLengthM(width_m);
    EXPECT_TRUE(IsOneTwoFive(length_m)) << width_m << " m: " << length_m;
    EXPECT_GE(length_m, 0.15 * width_m) << width_m;
    EXPECT_LE(length_m, 0.25 * width_m) << width_m;
  }
  EXPECT_DOUBLE_EQ(ScaleBarLengthM(27.0), 5.0);
  EXPECT_DOUBLE_EQ(ScaleBarLengthM(41.0), 10.0);
  EXPECT_DOUBLE_EQ(ScaleBarLengthM(4.0), 1.0);
}

TEST(ScaleBarTest, EveryWidthGetsARoundLengthNearAFifth) {
  for (double width_m = 0.5; width_m < 5000.0; width_m *= 1.07) {
    const double length_m = ScaleBarLengthM(width_m);
    ASSERT_TRUE(IsOneTwoFive(length_m)) << width_m << " m: " << length_m;
    EXPECT_LE(std::abs(std::log(length_m / (0.2 * width_m))), std::log(1.6)) << width_m;
    if (SomeOneTwoFiveFits(width_m)) {
      EXPECT_GE(length_m, 0.15 * width_m - 1e-9) << width_m;
      EXPECT_LE(length_m, 0.25 * width_m + 1e-9) << width_m;
    }
  }
  EXPECT_EQ(ScaleBarLengthM(0.0), 1.0);
  EXPECT_EQ(ScaleBarLengthM(-3.0), 1.0);
  EXPECT_EQ(ScaleBarLengthM(std::nan("")), 1.0);
}

TEST(ScaleBarTest, LabelIsInMetres) {
  EXPECT_EQ(ScaleBarLabel(5.0), "5 m");
  EXPECT_EQ(ScaleBarLabel(0.5), "0.5 m");
  EXPECT_EQ(ScaleBarLabel(20.0), "20 m");
  EXPECT_EQ(ScaleBarLabel(ScaleBarLengthM(1.3)), "0.2 m");
}

TEST(LegendLayoutTest, ColumnsAreBalancedAndFilledDownFirst) {
  const LegendStyle style;
  const Eigen::Vector2d footer(120.0, 2 * style.row_height_px);
  const LegendLayout twelve = LayoutLegend(12, 30.0, footer, 1000.0, style);
  EXPECT_EQ(twelve.rows, 6);
  EXPECT_EQ(twelve.columns, 2);
  const LegendLayout fifty = LayoutLegend(50, 30.0, footer, 1000.0, style);
  EXPECT_EQ(fifty.rows, 10);
  EXPECT_EQ(fifty.columns, 5);
  const LegendLayout eleven = LayoutLegend(11, 30.0, footer, 1000.0, style);
  EXPECT_EQ(eleven.rows, 6);
  EXPECT_EQ(eleven.columns, 2);
  const LegendLayout three = LayoutLegend(3, 30.0, footer, 1000.0, style);
  EXPECT_EQ(three.rows, 3);
  EXPECT_EQ(three.columns, 1);

  const double column_px = style.swatch_width_px + style.swatch_gap_px + 30.0;
  EXPECT_DOUBLE_EQ(twelve.column_width_px, column_px);
  EXPECT_DOUBLE_EQ(twelve.width_px, 2 * style.padding_px + 2 * column_px + style.column_gap_px);
  EXPECT_DOUBLE_EQ(twelve.footer_top_px, style.padding_px + 6 * style.row_height_px);
  EXPECT_DOUBLE_EQ(twelve.height_px, twelve.footer_top_px + footer.y() + style.padding_px);
  // Entry 7 (the eighth robot) is the second of the second column.
  const Eigen::Vector2d seventh = twelve.EntryOffsetPx(7, style);
  EXPECT_DOUBLE_EQ(seventh.x(), style.padding_px + column_px + style.column_gap_px);
  EXPECT_DOUBLE_EQ(seventh.y(), style.padding_px + style.row_height_px);
  EXPECT_EQ(twelve.EntryOffsetPx(0, style), Eigen::Vector2d::Constant(style.padding_px));
}

TEST(LegendLayoutTest, NarrowPicturesGetFewerLongerColumnsAndAWideFooterWidensTheBox) {
  const LegendStyle style;
  // Five columns of 57 px would be 353 px wide.
  const LegendLayout narrow = LayoutLegend(50, 30.0, Eigen::Vector2d::Zero(), 220.0, style);
  EXPECT_EQ(narrow.columns, 3);
  EXPECT_EQ(narrow.rows, 17);
  EXPECT_LE(narrow.width_px, 220.0);
  const LegendLayout too_narrow = LayoutLegend(50, 30.0, Eigen::Vector2d::Zero(), 10.0, style);
  EXPECT_EQ(too_narrow.columns, 1);
  EXPECT_EQ(too_narrow.rows, 50);
  const LegendLayout wide_footer = LayoutLegend(2, 10.0, Eigen::Vector2d(300.0, 16.0), 1e3);
  EXPECT_DOUBLE_EQ(wide_footer.width_px, 300.0 + 2 * style.padding_px);
  const LegendLayout none = LayoutLegend(0, 10.0, Eigen::Vector2d::Zero(), 1e3);
  EXPECT_EQ(none.rows, 0);
  EXPECT_EQ(none.width_px, 0.0);
}

TEST(CornerTest, BoxesGoWhereThePathsAreNot) {
  const Eigen::Vector2d picture(400.0, 300.0);
  const Eigen::Vector2d box(100.0, 80.0);
  const std::vector<Corner> all = {Corner::kTopRight, Corner::kTopLeft, Corner::kBottomRight,
                                   Corner::kBottomLeft};
  EXPECT_EQ(BoxOriginPx(Corner::kTopRight, picture, box, 8.0), Eigen::Vector2d(292.0, 8.0));
  EXPECT_EQ(BoxOriginPx(Corner::kBottomLeft, picture, box, 8.0), Eigen::Vector2d(8.0, 212.0));
  EXPECT_EQ(LeastCoveredCorner(picture, box, 8.0, {}, all), Corner::kTopRight);
  // Paths along the top edge: a bottom corner, the right one first.
  std::vector<Eigen::Vector2d> top_edge;
  for (double x = 0.0; x <= 400.0; x += 5.0) top_edge.emplace_back(x, 30.0);
  EXPECT_EQ(LeastCoveredCorner(picture, box, 8.0, top_edge, all), Corner::kBottomRight);
  // Paths in three corners: the fourth.
  const std::vector<Eigen::Vector2d> three = {{350, 40}, {50, 40}, {350, 250}};
  EXPECT_EQ(LeastCoveredCorner(picture, box, 8.0, three, all), Corner::kBottomLeft);
  EXPECT_EQ(LeastCoveredCorner(picture, box, 8.0, three, {Corner::kTopLeft, Corner::kTopRight}),
            Corner::kTopLeft);
  EXPECT_EQ(LeastCoveredCorner(picture, box, 8.0, three, {}), Corner::kTopRight);
}

TEST(CornerTest, PointsInBoxCountsTheEdgesIn) {
  const std::vector<Eigen::Vector2d> points = {{10, 10}, {20, 15}, {30, 30}, {9.9, 12}};
  EXPECT_EQ(PointsInBox({10, 10}, {10, 5}, points), 2u);
  EXPECT_EQ(PointsInBox({0, 0}, {100, 100}, points), 4u);
  EXPECT_EQ(PointsInBox({40, 40}, {10, 10}, points), 0u);
}

TEST(PathLabelTest, LabelsSitBeyondThePathEnds) {
  // A path east along y = 50 in device pixels.
  const std::vector<Eigen::Vector2d> east = {{10, 50}, {12, 50}, {40, 50}, {100, 50}};
  EXPECT_TRUE(AwayFromPath(east, true, 12.0).isApprox(Eigen::Vector2d(-1, 0)));
  EXPECT_TRUE(AwayFromPath(east, false, 12.0).isApprox(Eigen::Vector2d(1, 0)));
  // A short path: its far end sets the direction.
  EXPECT_TRUE(AwayFromPath({{0, 0}, {0, 3}}, true, 12.0).isApprox(Eigen::Vector2d(0, -1)));
  const Eigen::Vector2d up_right = Eigen::Vector2d(1, -1).normalized();
  EXPECT_TRUE(AwayFromPath({{5, 5}, {5, 5}}, false, 12.0).isApprox(up_right));
  EXPECT_TRUE(AwayFromPath({}, true, 12.0).isApprox(up_right));

  const Eigen::Vector2d text(30.0, 12.0);
  const Eigen::Vector2d end(100.0, 50.0);
  // East: the label's left edge 6 px beyond the end, centred on the path.
  EXPECT_TRUE(LabelCenterPx(end, {1, 0}, text, 6.0).isApprox(Eigen::Vector2d(121.0, 50.0)));
  // West: its right edge 6 px before.
  EXPECT_TRUE(LabelCenterPx(end, {-1, 0}, text, 6.0).isApprox(Eigen::Vector2d(79.0, 50.0)));
  // Up and right: its bottom-left corner on the diagonal; and, whichever way, the end point never
  // inside the box.
  const Eigen::Vector2d up_right_center = LabelCenterPx(end, up_right, text, 6.0);
  const Eigen::Vector2d bottom_left = up_right_center + 0.5 * Eigen::Vector2d(-text.x(), text.y());
  EXPECT_TRUE(bottom_left.isApprox(end + 6.0 * up_right));
  for (double angle_rad = 0.0; angle_rad < 6.3; angle_rad += 0.1) {
    const Eigen::Vector2d away(std::cos(angle_rad), std::sin(angle_rad));
    const Eigen::Vector2d center = LabelCenterPx(end, away, text, 6.0);
    EXPECT_FALSE(BoxesOverlap(center, text, end, Eigen::Vector2d::Constant(2.0))) << angle_rad;
  }
}

TEST(PathLabelTest, BoxesOverlap) {
  const Eigen::Vector2d size(10.0, 4.0);
  EXPECT_TRUE(BoxesOverlap({0, 0}, size, {9, 3}, size));
  EXPECT_FALSE(BoxesOverlap({0, 0}, size, {11, 0}, size));
  EXPECT_FALSE(BoxesOverlap({0, 0}, size, {0, 4}, size));
}

// A picture read back: the colour of pixel (x, y) as 0xRRGGBB.
class Picture {
 public:
  explicit Picture(const std::string& path)
      : surface_(cairo_image_surface_create_from_png(path.c_str())) {}
  ~Picture() { cairo_surface_destroy(surface_); }
  Picture(const Picture&) = delete;
  Picture& operator=(const Picture&) = delete;

  bool ok() const { return cairo_surface_status(surface_) == CAIRO_STATUS_SUCCESS; }
  int width() const { return cairo_image_surface_get_width(surface_); }
  int height() const { return cairo_image_surface_get_height(surface_); }
  uint32_t At(int x, int y) const {
    const unsigned char* row =
        cairo_image_surface_get_data(surface_) + y * cairo_image_surface_get_stride(surface_);
    uint32_t pixel = 0;
    std::memcpy(&pixel, row + 4 * x, sizeof(pixel));
    return pixel & 0xffffff;
  }

 private:
  cairo_surface_t* surface_;
};

bool Matches(uint32_t pixel, const Rgb& c) {
  const double channels[] = {c.r, c.g, c.b};
  for (int i = 0; i < 3; ++i) {
    const int have = static_cast<int>((pixel >> (16 - 8 * i)) & 0xff);
    if (std::abs(have - static_cast<int>(std::lround(255.0 * channels[i]))) > 3) return false;
  }
  return true;
}

// Whether a pixel within `radius` of (x, y) has colour `c`.
bool ColourNear(const Picture& picture, int x, int y, int radius, const Rgb& c) {
  for (int dy = -radius; dy <= radius; ++dy) {
    for (int dx = -radius; dx <= radius; ++dx) {
      const int px = x + dx;
      const int py = y + dy;
      if (px < 0 || py < 0 || px >= picture.width() || py >= picture.height()) continue;
      if (Matches(picture.At(px, py), c)) return true;
    }
  }
  return false;
}

std::string TempPicture(const std::string& ext) {
  return (std::filesystem::temp_directory_path() /
          absl::StrFormat("fleetnav_render_style_%d%s", getpid(), ext))
      .string();
}

// Twelve robots driving east, one a metre above the other, truth and estimate.
std::vector<TrajectoryTrace> TwelveRobots() {
  std::vector<TrajectoryTrace> traces;
  for (int i = 0; i < 12; ++i) {
    const std::string id = absl::StrFormat("r%02d", i + 1);
    const double y_m = 2.0 + i;
    traces.push_back({id, false, {{5.0, y_m}, {10.0, y_m}, {15.0, y_m}}});
    traces.push_back({id, true, {{5.0, y_m + 0.35}, {10.0, y_m + 0.35}, {15.0, y_m + 0.35}}});
  }
  return traces;
}

WorldDescription EmptyHall() {
  WorldDescription world;
  world.name = "hall";
  world.min_corner_m = Eigen::Vector2d(0.0, 0.0);
  world.max_corner_m = Eigen::Vector2d(20.0, 14.0);
  return world;
}

TEST(RenderWorldTest, TwelveRobotsEachInTheirOwnColour) {
  const std::string path = TempPicture(".png");
  RenderParams params;
  params.pixels_per_m = 40.0;
  params.margin_m = 0.5;
  ASSERT_TRUE(RenderWorld(EmptyHall(), TwelveRobots(), path, params).ok());
  ASSERT_TRUE(std::filesystem::exists(path));
  const Picture picture(path);
  ASSERT_TRUE(picture.ok());
  EXPECT_EQ(picture.width(), 21 * 40);
  EXPECT_EQ(picture.height(), 15 * 40);
  const std::vector<Rgb> colors = RobotColors(12);
  // The truth paths' middles: x = 10 m, y = 2 m (first robot) and 13 m (twelfth); the picture's
  // top left is (-0.5, 14.5) m.
  const int x_px = static_cast<int>(10.5 * 40);
  const int first_y_px = static_cast<int>((14.5 - 2.0) * 40);
  const int twelfth_y_px = static_cast<int>((14.5 - 13.0) * 40);
  EXPECT_TRUE(ColourNear(picture, x_px, first_y_px, 2, colors[0]));
  EXPECT_TRUE(ColourNear(picture, x_px, twelfth_y_px, 2, colors[11]));
  EXPECT_FALSE(ColourNear(picture, x_px, first_y_px, 2, colors[11]));
  EXPECT_FALSE(ColourNear(picture, x_px, twelfth_y_px, 2, colors[0]));
  std::filesystem::remove(path);
}

TEST(RenderWorldTest, TheLegendStandsBesideAMapWithoutAFreeCorner) {
  // Paths along all four edges of the hall: no corner is free.
  std::vector<TrajectoryTrace> traces = TwelveRobots();
  traces.push_back(
      {"rim", false, {{0.2, 0.2}, {19.8, 0.2}, {19.8, 13.8}, {0.2, 13.8}, {0.2, 0.2}}});
  const std::string path = TempPicture(".png");
  ASSERT_TRUE(RenderWorld(EmptyHall(), traces, path, RenderParams{}).ok());
  const Picture picture(path);
  ASSERT_TRUE(picture.ok());
  EXPECT_GT(picture.width(), 21 * 40 + 50);
  EXPECT_EQ(picture.height(), 15 * 40);
  // The thirteenth robot's colour shows in the legend right of the map.
  const Rgb rim = RobotColors(13)[12];
  bool in_legend = false;
  for (int y = 0; y < picture.height() && !in_legend; ++y) {
    for (int x = 21 * 40; x < picture.width() && !in_legend; ++x) {
      in_legend = Matches(picture.At(x, y), rim);
    }
  }
  EXPECT_TRUE(in_legend);
  std::filesystem::remove(path);
}

TEST(RenderWorldTest, DrawsSvgWithoutAnnotationsAndChecksTheFontSize) {
  const std::string path = TempPicture(".svg");
  RenderParams params;
  params.pixels_per_m = 10.0;
  ASSERT_TRUE(RenderWorld(EmptyHall(), TwelveRobots(), path, params).ok());
  EXPECT_GT(std::filesystem::file_size(path), 500u);
  params.legend = false;
  params.path_labels = false;
  params.scale_bar = false;
  ASSERT_TRUE(RenderWorld(EmptyHall(), TwelveRobots(), path, params).ok());
  std::filesystem::remove(path);
  params.font_size_px = 0.0;
  EXPECT_EQ(RenderWorld(EmptyHall(), {}, path, params).code(), absl::StatusCode::kInvalidArgument);
  EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
}  // namespace fleetnav::sim
