#include "fleetnav/core/zone.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <limits>

#include "fleetnav/core/robot_stop.hpp"

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

Polygon2 Square(double x0, double y0, double side) {
  return {{x0, y0}, {x0 + side, y0}, {x0 + side, y0 + side}, {x0, y0 + side}};
}

void ExpectInvalid(const absl::Status& status, const std::string& needle) {
  ASSERT_FALSE(status.ok()) << "expected an error containing '" << needle << "'";
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument) << status;
  EXPECT_THAT(std::string(status.message()), HasSubstr(needle));
}

constexpr char kBarnZones[] = R"(map: barn
zones:
  - name: pen-3
    kind: no_go
    polygon: [[1.0, 1.0], [3.0, 1.0], [3.0, 2.5], [1.0, 2.5]]
  - name: kitchen
    kind: speed_limit
    polygon: [[5, 0], [8, 0], [6.5, 2]]
    speed_limit: 0.3
  - name: door
    kind: one_at_a_time
    polygon: [[0, 4], [1, 4], [1, 5], [0, 5]]
    capacity: 2
)";

TEST(ZoneTest, ParsesEveryKindWithItsFigureAndWritesItBackTheSame) {
  absl::StatusOr<ZoneSet> zones = ParseZoneSetYaml(kBarnZones);
  ASSERT_TRUE(zones.ok()) << zones.status();
  EXPECT_EQ(zones->map_id, "barn");
  ASSERT_EQ(zones->zones.size(), 3u);
  EXPECT_EQ(zones->zones[0].kind, ZoneKind::kNoGo);
  EXPECT_EQ(zones->zones[0].polygon_in_map.size(), 4u);
  EXPECT_EQ(zones->zones[1].kind, ZoneKind::kSpeedLimit);
  EXPECT_DOUBLE_EQ(zones->zones[1].speed_limit_mps, 0.3);
  EXPECT_EQ(zones->zones[2].kind, ZoneKind::kOneAtATime);
  EXPECT_EQ(zones->zones[2].capacity, 2);

  absl::StatusOr<ZoneSet> again = ParseZoneSetYaml(ZoneSetToYaml(*zones));
  ASSERT_TRUE(again.ok()) << again.status();
  EXPECT_EQ(ZoneSetToYaml(*again), ZoneSetToYaml(*zones));
  EXPECT_EQ(again->zones[1].polygon_in_map[2], Eigen::Vector2d(6.5, 2.0));
}

TEST(ZoneTest, AnEmptySetIsValidAndLiftsEveryRule) {
  absl::StatusOr<ZoneSet> zones = ParseZoneSetYaml("zones: []\n");
  ASSERT_TRUE(zones.ok()) << zones.status();
  EXPECT_TRUE(zones->zones.empty());
  EXPECT_FALSE(zones->SpeedLimitAt({0, 0}, 1.0).has_value());
}

TEST(ZoneTest, BadZonesAreRefusedNamingTheField) {
  ExpectInvalid(
      ParseZoneSetYaml("zones:\n  - {name: a, kind: no_go, polygon: [[0,0],[1,1]]}\n").status(),
      "zones[0].polygon: needs at least 3 vertices");
  // A bow tie: edges 0-1 and 2-3 cross.
  ExpectInvalid(
      ParseZoneSetYaml("zones:\n  - {name: a, kind: no_go, polygon: [[0,0],[2,2],[2,0],[0,2]]}\n")
          .status(),
      "zones[0].polygon: edges 0-1 and 2-3 cross (self-intersecting)");
  ExpectInvalid(
      ParseZoneSetYaml("zones:\n  - {name: a, kind: no_go, polygon: [[0,0],[1,0],[2,0]]}\n")
          .status(),
      "degenerate");
  ExpectInvalid(
      ParseZoneSetYaml("zones:\n  - {name: a, kind: no_go, polygon: [[0,0],[0,0],[1,0],[1,1]]}\n")
          .status(),
      "zones[0].polygon: vertices 0 and 1 coincide");
  ExpectInvalid(ParseZoneSetYaml("zones:\n  - {name: s, kind: speed_limit, polygon: "
                                 "[[0,0],[1,0],[1,1]], speed_limit: 0}\n")
                    .status(),
                "zones[0].speed_limit: must be a finite speed > 0");
  ExpectInvalid(ParseZoneSetYaml("zones:\n  - {name: s, kind: speed_limit, polygon: "
                                 "[[0,0],[1,0],[1,1]], speed_limit: -0.5}\n")
                    .status(),
                "zones[0].speed_limit");
  ExpectInvalid(
      ParseZoneSetYaml("zones:\n  - {name: s, kind: speed_limit, polygon: [[0,0],[1,0],[1,1]]}\n")
          .status(),
      "missing 'speed_limit'");
  ExpectInvalid(ParseZoneSetYaml("zones:\n  - {name: n, kind: no_go, polygon: "
                                 "[[0,0],[1,0],[1,1]], speed_limit: 0.3}\n")
                    .status(),
                "zones[0].speed_limit: only a speed_limit zone has one");
  ExpectInvalid(ParseZoneSetYaml("zones:\n  - {name: d, kind: one_at_a_time, polygon: "
                                 "[[0,0],[1,0],[1,1]], capacity: 0}\n")
                    .status(),
                "zones[0].capacity: must be at least 1");
  ExpectInvalid(
      ParseZoneSetYaml("zones:\n  - {name: d, kind: closed, polygon: [[0,0],[1,0],[1,1]]}\n")
          .status(),
      "zones[0].kind: unknown zone kind 'closed'");
  ExpectInvalid(ParseZoneSetYaml("zones:\n  - {name: a, kind: no_go, polygon: [[0,0],[1,0],[1,1]]}"
                                 "\n  - {name: a, kind: no_go, polygon: [[5,0],[6,0],[6,1]]}\n")
                    .status(),
                "zones[1].name: zone 'a' is named twice");
  ExpectInvalid(
      ParseZoneSetYaml("zones:\n  - {name: 'a b', kind: no_go, polygon: [[0,0],[1,0],[1,1]]}\n")
          .status(),
      "zones[0].name");
  ExpectInvalid(
      ParseZoneSetYaml(
          "zones:\n  - {name: a, kind: no_go, polygon: [[0,0],[1,0],[1,1]], colour: red}\n")
          .status(),
      "zones[0]: unknown key 'colour'");
  ExpectInvalid(
      ParseZoneSetYaml("zones:\n  - {name: a, kind: no_go, polygon: [[0,0],[1,0],[1,.nan]]}\n")
          .status(),
      "zones[0].polygon[2]: not a finite point");
}

TEST(ZoneTest, ContainmentDistanceAndCrossingFollowTheOutline) {
  // An L shape: the notch at (1.5, 1.5) is outside.
  const Polygon2 l_shape = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  EXPECT_TRUE(PolygonContains(l_shape, {0.5, 0.5}));
  EXPECT_TRUE(PolygonContains(l_shape, {0.5, 1.5}));
  EXPECT_FALSE(PolygonContains(l_shape, {1.5, 1.5}));
  EXPECT_TRUE(PolygonContains(l_shape, {2.0, 0.5}));  // on the boundary
  EXPECT_NEAR(DistanceToPolygonBoundary(l_shape, {1.5, 1.5}), 0.5, 1e-12);
  EXPECT_NEAR(std::abs(PolygonArea(l_shape)), 3.0, 1e-12);
  EXPECT_FALSE(DiscTouchesPolygon(l_shape, {1.5, 1.5}, 0.49));
  EXPECT_TRUE(DiscTouchesPolygon(l_shape, {1.5, 1.5}, 0.51));
  // A segment in the notch only, its ends 0.224 m from the arms' inner corners.
  EXPECT_FALSE(SegmentTouchesPolygon(l_shape, {1.2, 2.1}, {2.1, 1.2}, 0.0));
  EXPECT_FALSE(SegmentTouchesPolygon(l_shape, {1.2, 2.1}, {2.1, 1.2}, 0.2));
  EXPECT_TRUE(SegmentTouchesPolygon(l_shape, {1.2, 2.1}, {2.1, 1.2}, 0.25));
  // A segment that crosses the square with both ends outside.
  EXPECT_TRUE(SegmentTouchesPolygon(Square(0, 0, 1), {-1, 0.5}, {2, 0.5}, 0.0));
}

TEST(ZoneTest, TheSpeedLimitIsTheLowestOfTheZonesTheRobotsDiscTouches) {
  ZoneSet zones;
  zones.zones.push_back({"slow", ZoneKind::kSpeedLimit, Square(0, 0, 2), 0.5, 1});
  zones.zones.push_back({"slower", ZoneKind::kSpeedLimit, Square(1.5, 0, 2), 0.2, 1});
  zones.zones.push_back({"pen", ZoneKind::kNoGo, Square(10, 10, 1), 0.0, 1});
  ASSERT_TRUE(zones.Validate().ok());
  EXPECT_DOUBLE_EQ(zones.SpeedLimitAt({0.5, 1.0}, 0.1).value(), 0.5);
  EXPECT_DOUBLE_EQ(zones.SpeedLimitAt({1.7, 1.0}, 0.1).value(), 0.2);
  // 0.4 m from "slow": within a grown disc of 0.5 m, not of 0.3 m.
  EXPECT_FALSE(zones.SpeedLimitAt({-0.4, 1.0}, 0.3).has_value());
  EXPECT_DOUBLE_EQ(zones.SpeedLimitAt({-0.4, 1.0}, 0.5).value(), 0.5);
  EXPECT_EQ(zones.Touching(ZoneKind::kNoGo, {10.5, 10.5}, 0.0).size(), 1u);
  EXPECT_EQ(zones.Find("pen")->kind, ZoneKind::kNoGo);
  EXPECT_EQ(zones.Find("barn"), nullptr);
}

TEST(ZoneTest, AZoneOffTheMapIsRefusedNamingTheVertex) {
  absl::StatusOr<OccupancyGrid> grid =
      OccupancyGrid::Filled(100, 50, 0.1, Pose2(0, 0, 0), int8_t{0});  // 10 m × 5 m
  ASSERT_TRUE(grid.ok());
  ZoneSet zones;
  zones.zones.push_back({"inside", ZoneKind::kNoGo, Square(1, 1, 2), 0.0, 1});
  EXPECT_TRUE(CheckZonesOnMap(zones, *grid).ok());
  zones.zones.push_back({"over", ZoneKind::kNoGo, Square(8, 3, 3), 0.0, 1});
  ExpectInvalid(CheckZonesOnMap(zones, *grid), "zones[1].polygon[1]");
}

TEST(ZoneTest, PlannersSeeNoGoZonesAsOccupiedCellsAndNothingElseChanges) {
  absl::StatusOr<OccupancyGrid> grid =
      OccupancyGrid::Filled(100, 50, 0.1, Pose2(0, 0, 0), int8_t{0});
  ASSERT_TRUE(grid.ok());
  grid->SetValue({90, 40}, -1);
  ZoneSet zones;
  zones.zones.push_back({"pen", ZoneKind::kNoGo, Square(2, 1, 1), 0.0, 1});
  zones.zones.push_back({"slow", ZoneKind::kSpeedLimit, Square(6, 1, 2), 0.3, 1});
  const OccupancyGrid marked = WithNoGoZonesOccupied(*grid, zones);
  int occupied = 0;
  for (int y = 0; y < marked.height(); ++y) {
    for (int x = 0; x < marked.width(); ++x) {
      const Eigen::Vector2d center = marked.CellToWorld({x, y});
      const bool in_pen =
          center.x() > 1.95 && center.x() < 3.05 && center.y() > 0.95 && center.y() < 2.05;
      if (marked.Value({x, y}) == 100) ++occupied;
      if (in_pen) {
        EXPECT_EQ(marked.Value({x, y}), 100) << x << "," << y;
      } else if (x != 90 || y != 40) {
        // Cells beside the pen may be marked (a cell the edge passes through); no others.
        const bool beside =
            center.x() > 1.85 && center.x() < 3.15 && center.y() > 0.85 && center.y() < 2.15;
        if (!beside) {
          EXPECT_EQ(marked.Value({x, y}), 0) << x << "," << y;
        }
      }
    }
  }
  EXPECT_GE(occupied, 100);  // the 1 m² pen is 100 cells
  EXPECT_LE(occupied, 144);  // and at most a ring of cells around it
  EXPECT_EQ(marked.Value({90, 40}), -1);
  EXPECT_EQ(marked.Value({70, 20}), 0);  // in the speed-limit zone
}

TEST(ZoneTest, FilesRoundTrip) {
  absl::StatusOr<ZoneSet> zones = ParseZoneSetYaml(kBarnZones);
  ASSERT_TRUE(zones.ok());
  const std::string path =
      (std::filesystem::temp_directory_path() / "fleetnav_zone_test.yaml").string();
  ASSERT_TRUE(SaveZoneSet(*zones, path).ok());
  absl::StatusOr<ZoneSet> loaded = LoadZoneSet(path);
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  EXPECT_EQ(ZoneSetToYaml(*loaded), ZoneSetToYaml(*zones));
  std::filesystem::remove(path);
  EXPECT_EQ(LoadZoneSet(path).status().code(), absl::StatusCode::kNotFound);
}

TEST(RobotStopTest, AStopAppliesToARobotWhoseReachTouchesItsZoneOrToAllForTheFleet) {
  RobotStop pen;
  pen.map_id = "barn";
  pen.zone = "pen";
  pen.polygon_in_map = {{0.0, 0.0}, {2.0, 0.0}, {2.0, 2.0}, {0.0, 2.0}};
  const std::vector<RobotStop> stops = {pen};
  EXPECT_NE(ApplyingStop(stops, "barn", {1.0, 1.0}, 0.5), nullptr);   // inside
  EXPECT_NE(ApplyingStop(stops, "barn", {-0.4, 1.0}, 0.5), nullptr);  // its reach over the edge
  EXPECT_EQ(ApplyingStop(stops, "barn", {-0.6, 1.0}, 0.5), nullptr);
  EXPECT_EQ(ApplyingStop(stops, "store", {1.0, 1.0}, 0.5), nullptr);  // another map's zone
  EXPECT_NE(ApplyingStop({RobotStop{}}, "store", {50.0, 50.0}, 0.5), nullptr);  // the fleet
}

}  // namespace
}  // namespace fleetnav
