#include "fleetnav/core/stripe_marker.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fleetnav/core/angles.hpp"

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

void ExpectInvalid(const absl::Status& status, const std::string& needle) {
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument) << status;
  EXPECT_THAT(std::string(status.message()), HasSubstr(needle));
}

TEST(NormalizeMarkerYawTest, WrapsToHalfOpenRange) {
  EXPECT_NEAR(NormalizeMarkerYaw(0.3), 0.3, 1e-12);
  EXPECT_DOUBLE_EQ(NormalizeMarkerYaw(-kPi / 2.0), -kPi / 2.0);
  EXPECT_NEAR(NormalizeMarkerYaw(kPi / 2.0), -kPi / 2.0, 1e-12);
  EXPECT_NEAR(NormalizeMarkerYaw(kPi), 0.0, 1e-12);
  EXPECT_NEAR(NormalizeMarkerYaw(3.0 * kPi / 4.0), -kPi / 4.0, 1e-12);
  EXPECT_NEAR(NormalizeMarkerYaw(-3.0 * kPi / 4.0), kPi / 4.0, 1e-12);
}

TEST(NormalizeMarkerYawTest, RandomYawsStayOnTheSameLine) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> yaw(-20.0, 20.0);
  for (int i = 0; i < 1000; ++i) {
    const double a = yaw(rng);
    const double n = NormalizeMarkerYaw(a);
    EXPECT_GE(n, -kPi / 2.0);
    EXPECT_LT(n, kPi / 2.0);
    // Same line: the directions are parallel (cross product zero).
    EXPECT_NEAR(std::cos(a) * std::sin(n) - std::sin(a) * std::cos(n), 0.0, 1e-9);
  }
}

TEST(YawFromQuaternionTest, ConvertsFloorQuaternions) {
  absl::StatusOr<double> identity = YawFromQuaternion(0, 0, 0, 1);
  ASSERT_TRUE(identity.ok());
  EXPECT_NEAR(*identity, 0.0, 1e-12);
  const double s = std::sin(kPi / 8.0);
  const double c = std::cos(kPi / 8.0);
  absl::StatusOr<double> yaw45 = YawFromQuaternion(0, 0, s, c);
  ASSERT_TRUE(yaw45.ok());
  EXPECT_NEAR(*yaw45, kPi / 4.0, 1e-12);
  // The thesis's 90-degree marker (c = d = 0.7071) is the line at -pi/2 in its range.
  absl::StatusOr<double> yaw90 = YawFromQuaternion(0, 0, 0.7071, 0.7071);
  ASSERT_TRUE(yaw90.ok());
  EXPECT_NEAR(*yaw90, -kPi / 2.0, 1e-4);
  // q and -q are the same rotation.
  absl::StatusOr<double> negated = YawFromQuaternion(0, 0, -s, -c);
  ASSERT_TRUE(negated.ok());
  EXPECT_NEAR(*negated, kPi / 4.0, 1e-12);
}

TEST(YawFromQuaternionTest, AcceptsSmallNormErrors) {
  absl::StatusOr<double> yaw = YawFromQuaternion(0, 0, 0, 1.0005);
  ASSERT_TRUE(yaw.ok()) << yaw.status();
  EXPECT_NEAR(*yaw, 0.0, 1e-12);
}

TEST(YawFromQuaternionTest, RejectsQuaternionNotOfUnitLength) {
  ExpectInvalid(YawFromQuaternion(0, 0, 0, 1.2).status(),
                "quaternion not of unit length (|q| = 1.2)");
  ExpectInvalid(YawFromQuaternion(0, 0, 0, 0).status(), "not of unit length");
  ExpectInvalid(YawFromQuaternion(0, 0, std::nan(""), 1).status(), "finite");
}

TEST(YawFromQuaternionTest, RejectsTiltedMarker) {
  const double half = 0.1;  // a roll of 0.2 rad
  ExpectInvalid(YawFromQuaternion(std::sin(half), 0, 0, std::cos(half)).status(),
                "out of the floor plane");
  ExpectInvalid(YawFromQuaternion(0, 0.01, 0.7071, 0.7071).status(), "b = 0.01");
}

TEST(QuaternionFromYawTest, RoundTripsThroughYawFromQuaternion) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> yaw(-kPi / 2.0, kPi / 2.0);
  for (int i = 0; i < 500; ++i) {
    const double expected = yaw(rng);
    const Eigen::Vector4d q = QuaternionFromYaw(expected);
    EXPECT_EQ(q[0], 0.0);
    EXPECT_EQ(q[1], 0.0);
    EXPECT_NEAR(q.norm(), 1.0, 1e-12);
    absl::StatusOr<double> back = YawFromQuaternion(q[0], q[1], q[2], q[3]);
    ASSERT_TRUE(back.ok());
    EXPECT_NEAR(*back, expected, 1e-12);
  }
}

TEST(LineTest, FootPointAndDistance) {
  const Line2 line{Eigen::Vector2d(1.0, 1.0), Eigen::Vector2d(1.0, 1.0).normalized()};
  const Eigen::Vector2d foot = FootPoint(line, {3.0, 1.0});
  EXPECT_NEAR((foot - Eigen::Vector2d(2.0, 2.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(DistanceToLine(line, {3.0, 1.0}), std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(DistanceToLine(line, {5.0, 5.0}), 0.0, 1e-12);
  // The foot point lies on the line and the offset is perpendicular to it.
  const Eigen::Vector2d p(-2.0, 7.0);
  const Eigen::Vector2d f = FootPoint(line, p);
  EXPECT_NEAR(DistanceToLine(line, f), 0.0, 1e-12);
  EXPECT_NEAR((p - f).dot(line.direction), 0.0, 1e-12);
}

TEST(StripeMarkerTest, AsLineAndCalibrationLine) {
  // Thesis §5.4.2: the calibration line passes through the sensor point, parallel to the marker.
  StripeMarker marker;
  marker.position_m = {5.0, 4.7};
  marker.yaw_rad = -kPi / 2.0;  // a stripe across a corridor running along x
  const Line2 line = marker.AsLine();
  EXPECT_NEAR(DistanceToLine(line, {5.0, -3.0}), 0.0, 1e-12);  // eq. 5.8: x = x0
  EXPECT_NEAR(DistanceToLine(line, {5.3, 4.7}), 0.3, 1e-12);
  const Line2 calibration = marker.CalibrationLine({4.8, 4.6});
  EXPECT_NEAR(DistanceToLine(calibration, {4.8, 10.0}), 0.0, 1e-12);
  // A particle at (5.5, 4.0) moves to its foot point (4.8, 4.0) on the calibration line.
  EXPECT_NEAR((FootPoint(calibration, {5.5, 4.0}) - Eigen::Vector2d(4.8, 4.0)).norm(), 0.0, 1e-12);
}

MarkerSet TwoMarkers() {
  MarkerSet set;
  set.map_id = "barn";
  StripeMarker a;
  a.id = 1;
  a.position_m = {0.0, 4.7};
  StripeMarker b;
  b.id = 2;
  b.position_m = {5.0, 4.7};
  set.markers = {a, b};
  return set;
}

TEST(MarkerSetTest, ValidateFindWithin) {
  const MarkerSet set = TwoMarkers();
  EXPECT_TRUE(set.Validate().ok());
  ASSERT_NE(set.Find(2), nullptr);
  EXPECT_DOUBLE_EQ(set.Find(2)->position_m.x(), 5.0);
  EXPECT_EQ(set.Find(3), nullptr);
  EXPECT_EQ(set.Within({0.5, 4.7}, 1.0).size(), 1u);
  EXPECT_EQ(set.Within({2.5, 4.7}, 2.5).size(), 2u);
  EXPECT_TRUE(set.Within({2.5, 0.0}, 1.0).empty());
}

TEST(MarkerSetTest, ValidateRejectsBadMarkers) {
  MarkerSet duplicate = TwoMarkers();
  duplicate.markers[1].id = 1;
  ExpectInvalid(duplicate.Validate(), "markers[1]: duplicate id 1");
  MarkerSet bad_length = TwoMarkers();
  bad_length.markers[0].length_m = 0.0;
  ExpectInvalid(bad_length.Validate(), "length_m must be finite and > 0");
  MarkerSet bad_position = TwoMarkers();
  bad_position.markers[1].position_m.x() = std::nan("");
  ExpectInvalid(bad_position.Validate(), "markers[1] (id 2): position must be finite");
  MarkerSet bad_yaw = TwoMarkers();
  bad_yaw.markers[0].yaw_rad = kPi / 2.0;
  ExpectInvalid(bad_yaw.Validate(), "yaw_rad must be in [-pi/2, pi/2)");
}

TEST(MarkerKindTest, NamesRoundTrip) {
  for (MarkerKind kind :
       {MarkerKind::kCalibration, MarkerKind::kFollowStripe, MarkerKind::kChargerStripe}) {
    absl::StatusOr<MarkerKind> parsed = ParseMarkerKind(MarkerKindName(kind));
    ASSERT_TRUE(parsed.ok());
    EXPECT_EQ(*parsed, kind);
  }
  ExpectInvalid(ParseMarkerKind("sticker").status(), "unknown marker kind 'sticker'");
}

}  // namespace
}  // namespace fleetnav
