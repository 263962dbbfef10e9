#include "fleetnav/proto/zone_convert.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

v1::Zone* AddTriangle(v1::ZoneSet& set, const std::string& name, v1::ZoneKind kind) {
  v1::Zone* zone = set.add_zones();
  zone->set_name(name);
  zone->set_kind(kind);
  for (auto [x, y] : {std::pair{0.0, 0.0}, {2.0, 0.0}, {1.0, 1.5}}) {
    v1::Point2* vertex = zone->add_polygon();
    vertex->set_x_m(x);
    vertex->set_y_m(y);
  }
  return zone;
}

TEST(ZoneConvertTest, EveryKindRoundTrips) {
  v1::ZoneSet wire;
  wire.set_map_id("barn");
  AddTriangle(wire, "pen", v1::ZONE_KIND_NO_GO);
  AddTriangle(wire, "kitchen", v1::ZONE_KIND_SPEED_LIMIT)->set_speed_limit_mps(0.3);
  AddTriangle(wire, "door", v1::ZONE_KIND_ONE_AT_A_TIME);  // capacity 0 reads as 1
  absl::StatusOr<ZoneSet> zones = FromProto(wire);
  ASSERT_TRUE(zones.ok()) << zones.status();
  EXPECT_EQ(zones->map_id, "barn");
  ASSERT_EQ(zones->zones.size(), 3u);
  EXPECT_EQ(zones->zones[1].kind, ZoneKind::kSpeedLimit);
  EXPECT_DOUBLE_EQ(zones->zones[1].speed_limit_mps, 0.3);
  EXPECT_EQ(zones->zones[2].capacity, 1);
  EXPECT_EQ(zones->zones[0].polygon_in_map[2], Eigen::Vector2d(1.0, 1.5));

  absl::StatusOr<ZoneSet> back = FromProto(ToProto(*zones));
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_EQ(ZoneSetToYaml(*back), ZoneSetToYaml(*zones));
}

TEST(ZoneConvertTest, BadZonesAreRefusedNamingTheField) {
  auto expect_refused = [](const v1::ZoneSet& wire, const std::string& needle) {
    absl::StatusOr<ZoneSet> zones = FromProto(wire);
    ASSERT_FALSE(zones.ok()) << needle;
    EXPECT_EQ(zones.status().code(), absl::StatusCode::kInvalidArgument);
    EXPECT_THAT(std::string(zones.status().message()), HasSubstr(needle));
  };
  v1::ZoneSet unspecified;
  AddTriangle(unspecified, "a", v1::ZONE_KIND_UNSPECIFIED);
  expect_refused(unspecified, "zones[0].kind");
  v1::ZoneSet no_limit;
  AddTriangle(no_limit, "a", v1::ZONE_KIND_SPEED_LIMIT);
  expect_refused(no_limit, "zones[0].speed_limit");
  v1::ZoneSet limit_on_no_go;
  AddTriangle(limit_on_no_go, "a", v1::ZONE_KIND_NO_GO)->set_speed_limit_mps(1.0);
  expect_refused(limit_on_no_go, "zones[0].speed_limit_mps: only a speed-limit zone");
  v1::ZoneSet nan_vertex;
  AddTriangle(nan_vertex, "a", v1::ZONE_KIND_NO_GO)
      ->mutable_polygon(1)
      ->set_x_m(std::numeric_limits<double>::quiet_NaN());
  expect_refused(nan_vertex, "zones[0].polygon[1]");
  v1::ZoneSet flat;
  AddTriangle(flat, "a", v1::ZONE_KIND_NO_GO)->mutable_polygon(2)->set_y_m(0.0);
  expect_refused(flat, "degenerate");
}

}  // namespace
}  // namespace fleetnav
