#include "fleetnav/proto/geometry_convert.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "fleetnav/core/angles.hpp"

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

template <typename T>
void ExpectInvalid(const absl::StatusOr<T>& result, const std::string& field) {
  ASSERT_FALSE(result.ok()) << "expected InvalidArgument naming '" << field << "'";
  EXPECT_EQ(result.status().code(), absl::StatusCode::kInvalidArgument) << result.status();
  EXPECT_THAT(std::string(result.status().message()), HasSubstr(field));
}

TEST(PoseConvertTest, RoundTripsExactly) {
  for (const Pose2& pose :
       {Pose2(), Pose2(1.5, -2.25, 0.3), Pose2(-1e6, 3e-9, -kPi / 2.0), Pose2(12.0, 7.0, kPi)}) {
    const v1::Pose2 wire = ToProto(pose);
    EXPECT_DOUBLE_EQ(wire.x_m(), pose.x_m());
    EXPECT_DOUBLE_EQ(wire.y_m(), pose.y_m());
    EXPECT_DOUBLE_EQ(wire.yaw_rad(), pose.yaw_rad());
    const absl::StatusOr<Pose2> back = FromProto(wire);
    ASSERT_TRUE(back.ok()) << back.status();
    EXPECT_EQ(back->x_m(), pose.x_m());
    EXPECT_EQ(back->y_m(), pose.y_m());
    EXPECT_EQ(back->yaw_rad(), pose.yaw_rad());
  }
}

TEST(PoseConvertTest, RefusesNonFiniteComponentsNamingTheField) {
  v1::Pose2 wire;
  wire.set_x_m(kNan);
  ExpectInvalid(FromProto(wire, "goal"), "goal");
  wire.set_x_m(0.0);
  wire.set_y_m(kInf);
  ExpectInvalid(FromProto(wire), "pose");
  wire.set_y_m(0.0);
  wire.set_yaw_rad(-kInf);
  ExpectInvalid(FromProto(wire, "job.start"), "job.start");
}

TEST(PointConvertTest, RoundTripsExactly) {
  const Eigen::Vector2d point(-3.5, 1e-3);
  const v1::Point2 wire = ToProto(point);
  EXPECT_EQ(wire.x_m(), -3.5);
  EXPECT_EQ(wire.y_m(), 1e-3);
  const absl::StatusOr<Eigen::Vector2d> back = FromProto(wire);
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_EQ(*back, point);
}

TEST(PointConvertTest, RefusesNanNamingTheField) {
  v1::Point2 wire;
  wire.set_y_m(kNan);
  ExpectInvalid(FromProto(wire, "waypoints[3]"), "waypoints[3]");
}

}  // namespace
}  // namespace fleetnav
