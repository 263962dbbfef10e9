#include "fleetnav/proto/map_convert.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "fleetnav/core/angles.hpp"

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

template <typename T>
void ExpectInvalid(const absl::StatusOr<T>& result, const std::string& field) {
  ASSERT_FALSE(result.ok()) << "expected InvalidArgument naming '" << field << "'";
  EXPECT_EQ(result.status().code(), absl::StatusCode::kInvalidArgument) << result.status();
  EXPECT_THAT(std::string(result.status().message()), HasSubstr(field));
}

// A 5 × 3 grid with free, occupied, unknown and in-between cells and a rotated origin.
OccupancyGrid SampleGrid() {
  std::vector<int8_t> cells = {0,   100, -1, 25, 65,  //
                               1,   50,  99, -1, 0,   //
                               100, 0,   0,  30, -1};
  absl::StatusOr<OccupancyGrid> grid =
      OccupancyGrid::Create(5, 3, 0.05, Pose2(-1.25, 2.5, 0.4), std::move(cells));
  EXPECT_TRUE(grid.ok()) << grid.status();
  return *grid;
}

v1::OccupancyGrid ValidWireGrid() { return ToProto(SampleGrid()); }

TEST(GridConvertTest, RoundTripsExactly) {
  const OccupancyGrid grid = SampleGrid();
  const v1::OccupancyGrid wire = ToProto(grid);
  EXPECT_EQ(wire.width(), 5u);
  EXPECT_EQ(wire.height(), 3u);
  EXPECT_EQ(wire.resolution_m(), 0.05);
  EXPECT_EQ(wire.origin().yaw_rad(), 0.4);
  ASSERT_EQ(wire.cells().size(), 15u);
  // Unknown cells travel as the byte 0xFF (two's complement of -1).
  EXPECT_EQ(static_cast<unsigned char>(wire.cells()[2]), 0xFFu);
  EXPECT_EQ(static_cast<unsigned char>(wire.cells()[1]), 100u);

  const absl::StatusOr<OccupancyGrid> back = FromProto(wire);
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_EQ(*back, grid);
  EXPECT_EQ(back->cells(), grid.cells());
  EXPECT_EQ(back->origin().x_m(), -1.25);
  EXPECT_EQ(back->origin().y_m(), 2.5);
  EXPECT_EQ(back->origin().yaw_rad(), 0.4);
}

TEST(GridConvertTest, RefusesCellCountThatDoesNotMatchWidthTimesHeight) {
  v1::OccupancyGrid wire = ValidWireGrid();
  wire.mutable_cells()->pop_back();
  ExpectInvalid(FromProto(wire), "grid.cells");
  wire = ValidWireGrid();
  wire.set_height(4);
  ExpectInvalid(FromProto(wire), "grid.cells");
}

TEST(GridConvertTest, RefusesGridOverTheCellLimitBeforeLookingAtCells) {
  v1::OccupancyGrid wire = ValidWireGrid();
  wire.set_width(100'000);
  wire.set_height(100'000);  // 1e10 cells, far above kMaxGridCells
  const absl::StatusOr<OccupancyGrid> result = FromProto(wire);
  ExpectInvalid(result, "grid");
  EXPECT_THAT(std::string(result.status().message()), HasSubstr("exceeds the limit"));

  // One cell over the limit is refused too; exactly at the limit is only a cell-count mismatch.
  wire.set_width(static_cast<uint32_t>(kMaxGridCells) + 1);
  wire.set_height(1);
  EXPECT_THAT(std::string(FromProto(wire).status().message()), HasSubstr("exceeds the limit"));
  wire.set_width(static_cast<uint32_t>(kMaxGridCells));
  ExpectInvalid(FromProto(wire), "grid.cells");
}

TEST(GridConvertTest, RefusesNanResolution) {
  v1::OccupancyGrid wire = ValidWireGrid();
  wire.set_resolution_m(kNan);
  ExpectInvalid(FromProto(wire), "resolution_m");
  wire.set_resolution_m(0.0);
  ExpectInvalid(FromProto(wire), "resolution_m");
}

TEST(GridConvertTest, RefusesNanOrigin) {
  v1::OccupancyGrid wire = ValidWireGrid();
  wire.mutable_origin()->set_yaw_rad(kNan);
  ExpectInvalid(FromProto(wire), "grid.origin");
}

TEST(GridConvertTest, RefusesEmptyGridAndOutOfRangeCells) {
  v1::OccupancyGrid empty;
  empty.set_resolution_m(0.05);
  ExpectInvalid(FromProto(empty), "width");

  v1::OccupancyGrid wire = ValidWireGrid();
  (*wire.mutable_cells())[7] = static_cast<char>(101);
  ExpectInvalid(FromProto(wire), "cells[7]");
}

StripeMarker Marker(int id, double x, double y, double yaw, double length, MarkerKind kind) {
  StripeMarker marker;
  marker.id = id;
  marker.position_m = {x, y};
  marker.yaw_rad = yaw;
  marker.length_m = length;
  marker.kind = kind;
  return marker;
}

void ExpectSameMarker(const StripeMarker& actual, const StripeMarker& expected) {
  EXPECT_EQ(actual.id, expected.id);
  EXPECT_EQ(actual.position_m, expected.position_m);
  EXPECT_NEAR(actual.yaw_rad, expected.yaw_rad, 1e-12);
  EXPECT_EQ(actual.length_m, expected.length_m);
  EXPECT_EQ(actual.kind, expected.kind);
}

TEST(MarkerConvertTest, RoundTripsEveryKind) {
  for (const StripeMarker& marker :
       {Marker(1, 0.0, 4.7, kPi / 4.0, 0.5, MarkerKind::kCalibration),
        Marker(2, -3.0, 1.0, -kPi / 2.0, 2.0, MarkerKind::kFollowStripe),
        Marker(7, 10.0, -0.5, 0.0, 0.3, MarkerKind::kChargerStripe)}) {
    const v1::StripeMarker wire = ToProto(marker);
    EXPECT_EQ(wire.kind(), marker.kind == MarkerKind::kCalibration ? v1::MARKER_KIND_CALIBRATION
                           : marker.kind == MarkerKind::kFollowStripe
                               ? v1::MARKER_KIND_FOLLOW_STRIPE
                               : v1::MARKER_KIND_CHARGER_STRIPE);
    const absl::StatusOr<StripeMarker> back = FromProto(wire);
    ASSERT_TRUE(back.ok()) << back.status();
    ExpectSameMarker(*back, marker);
  }
}

TEST(MarkerConvertTest, NormalizesYawToTheStripeRange) {
  v1::StripeMarker wire = ToProto(Marker(3, 1.0, 2.0, 0.0, 0.5, MarkerKind::kCalibration));
  wire.mutable_pose()->set_yaw_rad(3.0 * kPi / 4.0);  // the same line as -pi/4
  const absl::StatusOr<StripeMarker> back = FromProto(wire);
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_NEAR(back->yaw_rad, -kPi / 4.0, 1e-12);
}

TEST(MarkerConvertTest, UnspecifiedKindMeansCalibration) {
  v1::StripeMarker wire = ToProto(Marker(3, 1.0, 2.0, 0.0, 0.5, MarkerKind::kFollowStripe));
  wire.set_kind(v1::MARKER_KIND_UNSPECIFIED);
  const absl::StatusOr<StripeMarker> back = FromProto(wire);
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_EQ(back->kind, MarkerKind::kCalibration);
}

TEST(MarkerConvertTest, RefusesZeroOrNanLength) {
  v1::StripeMarker wire = ToProto(Marker(3, 1.0, 2.0, 0.0, 0.5, MarkerKind::kCalibration));
  wire.set_length_m(0.0);
  ExpectInvalid(FromProto(wire), "marker.length_m");
  wire.set_length_m(-0.5);
  ExpectInvalid(FromProto(wire), "marker.length_m");
  wire.set_length_m(kNan);
  ExpectInvalid(FromProto(wire), "marker.length_m");
}

TEST(MarkerConvertTest, RefusesUnknownKind) {
  v1::StripeMarker wire = ToProto(Marker(3, 1.0, 2.0, 0.0, 0.5, MarkerKind::kCalibration));
  wire.set_kind(static_cast<v1::MarkerKind>(99));
  const absl::StatusOr<StripeMarker> result = FromProto(wire);
  ExpectInvalid(result, "marker.kind");
  EXPECT_THAT(std::string(result.status().message()), HasSubstr("99"));
}

TEST(MarkerConvertTest, RefusesNanPose) {
  v1::StripeMarker wire = ToProto(Marker(3, 1.0, 2.0, 0.0, 0.5, MarkerKind::kCalibration));
  wire.mutable_pose()->set_x_m(kNan);
  ExpectInvalid(FromProto(wire), "marker.pose");
}

MarkerSet SampleMarkerSet() {
  MarkerSet set;
  set.map_id = "barn";
  set.markers = {Marker(1, 0.0, 4.7, kPi / 4.0, 0.5, MarkerKind::kCalibration),
                 Marker(2, -3.0, 1.0, -kPi / 2.0, 2.0, MarkerKind::kFollowStripe),
                 Marker(9, 10.0, -0.5, 1.0, 0.3, MarkerKind::kChargerStripe)};
  return set;
}

TEST(MarkerSetConvertTest, RoundTrips) {
  const MarkerSet set = SampleMarkerSet();
  const v1::MarkerSet wire = ToProto(set);
  EXPECT_EQ(wire.map_id(), "barn");
  ASSERT_EQ(wire.markers_size(), 3);
  const absl::StatusOr<MarkerSet> back = FromProto(wire);
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_EQ(back->map_id, set.map_id);
  ASSERT_EQ(back->markers.size(), set.markers.size());
  for (size_t i = 0; i < set.markers.size(); ++i)
    ExpectSameMarker(back->markers[i], set.markers[i]);
}

TEST(MarkerSetConvertTest, EmptySetRoundTrips) {
  MarkerSet set;
  set.map_id = "empty";
  const absl::StatusOr<MarkerSet> back = FromProto(ToProto(set));
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_EQ(back->map_id, "empty");
  EXPECT_TRUE(back->markers.empty());
}

TEST(MarkerSetConvertTest, NamesTheIndexOfABadMarker) {
  v1::MarkerSet wire = ToProto(SampleMarkerSet());
  wire.mutable_markers(1)->set_length_m(0.0);
  ExpectInvalid(FromProto(wire), "markers[1].length_m");
  wire = ToProto(SampleMarkerSet());
  wire.mutable_markers(2)->set_kind(static_cast<v1::MarkerKind>(99));
  ExpectInvalid(FromProto(wire), "markers[2].kind");
}

TEST(MarkerSetConvertTest, RefusesDuplicateIds) {
  v1::MarkerSet wire = ToProto(SampleMarkerSet());
  wire.mutable_markers(2)->set_id(1);
  const absl::StatusOr<MarkerSet> result = FromProto(wire);
  ExpectInvalid(result, "markers[2]");
  EXPECT_THAT(std::string(result.status().message()), HasSubstr("duplicate id 1"));
}

}  // namespace
}  // namespace fleetnav
