#include "fleetnav/robot_agent/zone_speed_limit.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace fleetnav::agent {
namespace {

ZoneSet Checkout() {
  ZoneSet zones;
  zones.map_id = "store";
  // 0.3 m/s from x = 5 to 8; a stricter 0.1 m/s at x = 20.
  zones.zones.push_back(
      {"checkout", ZoneKind::kSpeedLimit, {{5, 0}, {8, 0}, {8, 3}, {5, 3}}, 0.3, 1});
  zones.zones.push_back(
      {"crossing", ZoneKind::kSpeedLimit, {{20, 0}, {21, 0}, {21, 3}, {20, 3}}, 0.1, 1});
  zones.zones.push_back({"pen", ZoneKind::kNoGo, {{0, 0}, {1, 0}, {1, 1}}, 0.0, 1});
  return zones;
}

TEST(ZoneSpeedLimitTest, InsideAZoneItsLimitHoldsAndAwayFromItTheBrakingEnvelope) {
  const Eigen::Matrix3d certain = Eigen::Matrix3d::Zero();
  ZoneSpeedParams params;
  params.braking_decel_mps2 = 0.5;
  EXPECT_DOUBLE_EQ(*ZoneSpeedCap(Checkout(), Pose2(6, 1, 0), certain, 0.4, params), 0.3);
  // Within the footprint's radius of the edge: the limit already.
  EXPECT_DOUBLE_EQ(*ZoneSpeedCap(Checkout(), Pose2(4.7, 1, 0), certain, 0.4, params), 0.3);
  // 1.6 m out with a 0.4 m radius: a gap of 1.2 m, v = sqrt(0.09 + 2 · 0.5 · 1.2).
  EXPECT_NEAR(*ZoneSpeedCap(Checkout(), Pose2(3.4, 1, 0), certain, 0.4, params),
              std::sqrt(0.09 + 1.2), 1e-9);
  // No speed-limit zone at all: no cap (a no-go zone is not one).
  ZoneSet no_go_only = Checkout();
  no_go_only.zones.erase(no_go_only.zones.begin(), no_go_only.zones.begin() + 2);
  EXPECT_FALSE(ZoneSpeedCap(no_go_only, Pose2(0.5, 0.5, 0), certain, 0.4, params).has_value());
}

TEST(ZoneSpeedLimitTest, AnUncertainEstimateReachesTheZoneSooner) {
  ZoneSpeedParams params;
  params.sigma_multiple = 2.0;
  Eigen::Matrix3d uncertain = Eigen::Matrix3d::Zero();
  uncertain(0, 0) = 0.25 * 0.25;  // σx = 0.25 m
  uncertain(1, 1) = 0.01 * 0.01;
  // 0.8 m from the edge, radius 0.4 m: a certain robot is 0.4 m short of the zone; one with
  // σ = 0.25 m grown by 2σ is in it.
  const Pose2 near(4.2, 1, 0);
  EXPECT_GT(*ZoneSpeedCap(Checkout(), near, Eigen::Matrix3d::Zero(), 0.4, params), 0.3 + 1e-3);
  EXPECT_DOUBLE_EQ(*ZoneSpeedCap(Checkout(), near, uncertain, 0.4, params), 0.3);
}

TEST(ZoneSpeedLimitTest, TheLowestOfTheZonesHolds) {
  // Between the two zones, nearer the strict one: its envelope is the lower.
  const double cap = *ZoneSpeedCap(Checkout(), Pose2(19.0, 1, 0), Eigen::Matrix3d::Zero(), 0.4);
  EXPECT_NEAR(cap, std::sqrt(0.01 + 2 * 0.4 * 0.6), 1e-9);
}

TEST(ZoneSpeedLimitTest, ACappedTwistKeepsItsCurvature) {
  const Twist2 fast{0.6, 0.8, 0.5};  // 1 m/s
  const Twist2 capped = CapTwist(fast, 0.25);
  EXPECT_NEAR(std::hypot(capped.vx_mps, capped.vy_mps), 0.25, 1e-12);
  EXPECT_NEAR(capped.yaw_rate_radps / std::hypot(capped.vx_mps, capped.vy_mps), 0.5, 1e-12);
  const Twist2 slow{0.1, 0.0, 0.3};
  EXPECT_DOUBLE_EQ(CapTwist(slow, 0.25).yaw_rate_radps, 0.3);
  const Twist2 turning{0.0, 0.0, 1.0};  // turning in place has no speed to cap
  EXPECT_DOUBLE_EQ(CapTwist(turning, 0.1).yaw_rate_radps, 1.0);
}

TEST(ZoneSpeedLimitTest, BadParamsAreRefusedNamingTheField) {
  ZoneSpeedParams params;
  params.braking_decel_mps2 = 0.0;
  EXPECT_EQ(params.Validate().code(), absl::StatusCode::kInvalidArgument);
  params = {};
  params.sigma_multiple = -1.0;
  EXPECT_NE(params.Validate().message().find("sigma_multiple"), std::string::npos);
  EXPECT_TRUE(ZoneSpeedParams{}.Validate().ok());
}

}  // namespace
}  // namespace fleetnav::agent
