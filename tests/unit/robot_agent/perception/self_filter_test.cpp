#include "fleetnav/robot_agent/self_filter.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "fleetnav/core/angles.hpp"

namespace fleetnav::agent {
namespace {

// The mecanum platform's laser looks forward from 0.35 m ahead of base_link; one beam at 0 rad
// ends 0.2 m ahead of it (inside a carried trolley's box), one at 30° ends 2 m away.
SensorFrame FrameWithTwoReturns() {
  SensorFrame frame;
  LaserScanSample scan;
  scan.name = "laser";
  scan.angle_min_rad = 0.0;
  scan.angle_increment_rad = kPi / 6;
  scan.range_max_m = 10.0;
  scan.ranges_m = {0.2f, 2.0f};
  frame.lasers.push_back(scan);
  return frame;
}

TEST(SelfFilterTest, ReturnsInsideTheCarriedLoadAreDroppedAndOthersKept) {
  const SelfFilter filter(MecanumPlatformModel(), 0.05);
  SensorFrame frame = FrameWithTwoReturns();
  filter.Apply(Eigen::Vector2d(1.2, 0.8), &frame);
  EXPECT_TRUE(std::isnan(frame.lasers[0].ranges_m[0]));
  EXPECT_FLOAT_EQ(frame.lasers[0].ranges_m[1], 2.0f);
}

TEST(SelfFilterTest, NothingCarriedNothingDropped) {
  const SelfFilter filter(MecanumPlatformModel(), 0.05);
  SensorFrame frame = FrameWithTwoReturns();
  filter.Apply(std::nullopt, &frame);
  EXPECT_FLOAT_EQ(frame.lasers[0].ranges_m[0], 0.2f);
  EXPECT_FLOAT_EQ(frame.lasers[0].ranges_m[1], 2.0f);
}

}  // namespace
}  // namespace fleetnav::agent
