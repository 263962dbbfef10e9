// The PNG that `fleetnavctl map render` writes, read back pixel by pixel.
#include "fleetnav/ctl/map_render.hpp"

#include <cairo.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <memory>

#include "fleetnav/core/angles.hpp"

namespace fleetnav::ctl {
namespace {

struct Pixel {
  int r, g, b;
};

/// A PNG read back with cairo; pixel (x, y) counts from the top-left corner.
class PngImage {
 public:
  explicit PngImage(const std::string& path)
      : surface_(cairo_image_surface_create_from_png(path.c_str()), cairo_surface_destroy) {}
  bool ok() const { return cairo_surface_status(surface_.get()) == CAIRO_STATUS_SUCCESS; }
  int width() const { return cairo_image_surface_get_width(surface_.get()); }
  int height() const { return cairo_image_surface_get_height(surface_.get()); }
  Pixel At(int x, int y) const {
    const unsigned char* row =
        cairo_image_surface_get_data(surface_.get()) +
        static_cast<size_t>(cairo_image_surface_get_stride(surface_.get())) * y;
    const uint32_t argb = reinterpret_cast<const uint32_t*>(row)[x];
    return {static_cast<int>((argb >> 16) & 0xff), static_cast<int>((argb >> 8) & 0xff),
            static_cast<int>(argb & 0xff)};
  }

 private:
  std::unique_ptr<cairo_surface_t, void (*)(cairo_surface_t*)> surface_;
};

std::string TempPng(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          (name + "-" + std::to_string(::getpid()) + ".png"))
      .string();
}

/// A 10 m x 5 m map at 0.1 m: free, an occupied wall along x = 8 m, unknown above y = 4 m.
OccupancyGrid TestGrid() {
  OccupancyGrid grid = *OccupancyGrid::Filled(100, 50, 0.1, Pose2(), OccupancyGrid::kFreeValue);
  for (int y = 0; y < 40; ++y) grid.SetValue({80, y}, OccupancyGrid::kOccupiedValue);
  for (int y = 40; y < 50; ++y) {
    for (int x = 0; x < 100; ++x) grid.SetValue({x, y}, OccupancyGrid::kUnknownValue);
  }
  return grid;
}

TEST(MapRenderTest, CellsMarkersAndRoutesLandWhereTheMapPutsThem) {
  MarkerSet markers;
  markers.map_id = "barn";
  StripeMarker calibration;
  calibration.id = 1;
  calibration.position_m = {2.0, 1.0};
  calibration.yaw_rad = kPi / 2;  // a stripe along y from (2, 0.75) to (2, 1.25)
  markers.markers.push_back(calibration);
  Route route;
  route.name = "aisle";
  route.map_id = "barn";
  FreeNavigationAction nav;
  nav.waypoints_m = {{5.0, 0.5}};
  nav.goal = Pose2(5.0, 3.5, 0.0);
  route.actions.push_back({nav, {EndConditionKind::kGoalReached, 0}});
  const std::string path = TempPng("render");
  ASSERT_TRUE(RenderSiteMapPng({TestGrid(), markers, {route}}, path, {.pixels_per_cell = 4}).ok());

  const PngImage png(path);
  ASSERT_TRUE(png.ok());
  ASSERT_EQ(png.width(), 400);
  ASSERT_EQ(png.height(), 200);
  // Image y = 200 - 40 * y_m. A free cell is 254 grey, the wall black, unknown 205.
  const Pixel free = png.At(120, 140);  // (3.0 m, 1.5 m)
  EXPECT_EQ(free.r, 254);
  EXPECT_EQ(free.b, 254);
  const Pixel wall = png.At(322, 150);  // inside cell x 80 at y 1.25 m
  EXPECT_EQ(wall.r, 0);
  const Pixel unknown = png.At(380, 10);  // (9.5 m, 4.75 m)
  EXPECT_EQ(unknown.r, 205);
  EXPECT_EQ(unknown.g, 205);
  // The calibration marker in gold at (2 m, 1 m).
  const Pixel marker = png.At(80, 160);
  EXPECT_GT(marker.r, 200);
  EXPECT_GT(marker.g, 150);
  EXPECT_LT(marker.b, 50);
  // The route's line from waypoint (5, 0.5) to goal (5, 3.5) in the first route colour (red).
  const Pixel route_line = png.At(200, 100);  // (5 m, 2.5 m)
  EXPECT_GT(route_line.r, 180);
  EXPECT_LT(route_line.g, 60);
  // Beside the line the floor is still free.
  EXPECT_EQ(png.At(210, 100).g, 254);
  std::filesystem::remove(path);
}

TEST(MapRenderTest, AGridTurnedByItsOriginIsDrawnInItsOwnCells) {
  // The grid's origin at (10, 0) turned by 90°: map point (9.5, 2) is grid point (2, 0.5).
  OccupancyGrid grid =
      *OccupancyGrid::Filled(50, 20, 0.1, Pose2(10.0, 0.0, kPi / 2), OccupancyGrid::kFreeValue);
  Route route;
  route.name = "turned";
  route.map_id = "barn";
  FreeNavigationAction nav;
  nav.waypoints_m = {{9.9, 1.0}};
  nav.goal = Pose2(9.9, 4.0, 0.0);
  route.actions.push_back({nav, {EndConditionKind::kGoalReached, 0}});
  const std::string path = TempPng("render-turned");
  ASSERT_TRUE(RenderSiteMapPng({grid, std::nullopt, {route}}, path, {.pixels_per_cell = 4}).ok());
  const PngImage png(path);
  ASSERT_TRUE(png.ok());
  // Map (9.9, 2.5) is grid (2.5, 0.1) → image (100, 80 - 4) = (100, 76).
  const Pixel on_line = png.At(100, 76);
  EXPECT_GT(on_line.r, 180);
  EXPECT_LT(on_line.g, 60);
  std::filesystem::remove(path);
}

TEST(MapRenderTest, ADefaultScaleKeepsTheLongerSideNear1600Pixels) {
  EXPECT_EQ(PixelsPerCell(TestGrid(), {}), 8);  // 100 cells: capped at 8
  const OccupancyGrid wide = *OccupancyGrid::Filled(800, 100, 0.05, Pose2(), 0);
  EXPECT_EQ(PixelsPerCell(wide, {}), 2);
  const OccupancyGrid huge = *OccupancyGrid::Filled(4000, 10, 0.05, Pose2(), 0);
  EXPECT_EQ(PixelsPerCell(huge, {}), 1);
}

TEST(MapRenderTest, BadPathsAndScalesAreRefusedWithTheReason) {
  const absl::Status svg = RenderSiteMapPng({TestGrid(), std::nullopt, {}}, "/tmp/map.svg");
  EXPECT_EQ(svg.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(svg.message().find(".png"), std::string::npos) << svg;
  const absl::Status scale =
      RenderSiteMapPng({TestGrid(), std::nullopt, {}}, TempPng("scale"), {.pixels_per_cell = 65});
  EXPECT_EQ(scale.code(), absl::StatusCode::kInvalidArgument);
  const absl::Status missing_dir =
      RenderSiteMapPng({TestGrid(), std::nullopt, {}}, "/nonexistent-dir/map.png");
  EXPECT_EQ(missing_dir.code(), absl::StatusCode::kInternal);
  EXPECT_NE(missing_dir.message().find("/nonexistent-dir/map.png"), std::string::npos);
}

}  // namespace
}  // namespace fleetnav::ctl
