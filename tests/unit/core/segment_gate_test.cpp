#include "fleetnav/core/segment_gate.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "fleetnav/core/angles.hpp"

namespace fleetnav {
namespace {

TEST(SegmentGateTest, DistanceIsMeasuredAlongTheDirectionOfTravel) {
  const Pose2 gate(3.0, 1.0, kPi / 2);  // travel north through (3, 1)
  EXPECT_NEAR(DistanceBeforeGate(gate, {3.0, -1.0}), 2.0, 1e-12);
  EXPECT_NEAR(DistanceBeforeGate(gate, {5.0, -1.0}), 2.0, 1e-12);  // sideways does not count
  EXPECT_NEAR(DistanceBeforeGate(gate, {3.0, 1.5}), -0.5, 1e-12);
}

TEST(SegmentGateTest, AGateIsReachedJustBeforeItsLineAndNearItsPointOnly) {
  const Pose2 gate(0.0, 0.0, 0.0);
  EXPECT_TRUE(ReachedGate(gate, {-0.15, 0.0}));
  EXPECT_TRUE(ReachedGate(gate, {0.5, 0.3}));
  EXPECT_FALSE(ReachedGate(gate, {-0.5, 0.0}));  // still before it
  EXPECT_FALSE(ReachedGate(gate, {0.5, 2.0}));   // past the line, but elsewhere
}

TEST(SegmentGateTest, TheSpeedLimitStopsTheRobotJustBeforeTheGate) {
  const Pose2 gate(0.0, 0.0, 0.0);
  const Eigen::Vector2d east(1.0, 0.0);
  // √(2 · 0.5 · (2.1 − 0.1)) = √2.
  EXPECT_NEAR(SpeedLimitBeforeGate(gate, {-2.1, 0.0}, east, 0.5), std::sqrt(2.0), 1e-9);
  EXPECT_EQ(SpeedLimitBeforeGate(gate, {-0.05, 0.0}, east, 0.5), 0.0);
  EXPECT_EQ(SpeedLimitBeforeGate(gate, {0.3, 0.0}, east, 0.5), 0.0);  // overshot: stand
  // Far from the gate, or driving away from its direction: no limit.
  EXPECT_GT(SpeedLimitBeforeGate(gate, {-3.0, 0.0}, east, 0.5), 1e6);
  EXPECT_GT(SpeedLimitBeforeGate(gate, {0.3, 0.0}, -east, 0.5), 1e6);
}

}  // namespace
}  // namespace fleetnav
