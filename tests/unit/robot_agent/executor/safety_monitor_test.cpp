#include "fleetnav/robot_agent/safety_monitor.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace fleetnav::agent {
namespace {

using ::testing::HasSubstr;

constexpr double kDt = 0.02;

TEST(SafetyMonitorTest, BumperStopsAtOnceAndLatches) {
  SafetyMonitor monitor;
  Perception perception;
  EXPECT_EQ(monitor.Check(perception, Twist2{0.3, 0, 0}, Twist2{0.3, 0, 0}, false, kDt).stop,
            SafetyStop::kNone);
  perception.bumper = true;
  EXPECT_EQ(monitor.Check(perception, Twist2{0.3, 0, 0}, Twist2{0.3, 0, 0}, false, kDt).stop,
            SafetyStop::kBumper);
  perception.bumper = false;  // latched until Reset
  EXPECT_EQ(monitor.Check(perception, Twist2{}, Twist2{}, false, kDt).stop, SafetyStop::kBumper);
  monitor.Reset();
  EXPECT_EQ(monitor.Check(perception, Twist2{}, Twist2{}, false, kDt).stop, SafetyStop::kNone);
}

TEST(SafetyMonitorTest, StallAfterTwoSecondsOfCommandedMotionWithoutMotion) {
  SafetyMonitor monitor;
  const Perception perception;
  int ticks = 0;
  while (monitor.Check(perception, Twist2{0.25, 0, 0}, Twist2{0.001, 0, 0}, false, kDt).stop ==
             SafetyStop::kNone &&
         ticks < 1000) {
    ++ticks;
  }
  EXPECT_NEAR(ticks * kDt, 2.0, 2 * kDt);
  EXPECT_EQ(monitor.verdict().stop, SafetyStop::kStall);
  EXPECT_THAT(monitor.verdict().reason, HasSubstr("stalled"));
}

TEST(SafetyMonitorTest, StandingStillOnPurposeOrMovingIsNoStall) {
  SafetyMonitor monitor;
  const Perception perception;
  for (int i = 0; i < 500; ++i) {
    ASSERT_EQ(monitor.Check(perception, Twist2{}, Twist2{}, false, kDt).stop, SafetyStop::kNone);
    ASSERT_EQ(monitor.Check(perception, Twist2{0, 0, 0.3}, Twist2{0, 0, 0.29}, false, kDt).stop,
              SafetyStop::kNone);
  }
}

TEST(SafetyMonitorTest, LostLocalizationStopsAfterItsGracePeriod) {
  SafetyMonitor monitor;
  const Perception perception;
  EXPECT_EQ(monitor.Check(perception, Twist2{}, Twist2{}, true, 0.2).stop, SafetyStop::kNone);
  EXPECT_EQ(monitor.Check(perception, Twist2{}, Twist2{}, false, 0.2).stop, SafetyStop::kNone);
  EXPECT_EQ(monitor.Check(perception, Twist2{}, Twist2{}, true, 0.3).stop, SafetyStop::kNone);
  EXPECT_EQ(monitor.Check(perception, Twist2{}, Twist2{}, true, 0.3).stop,
            SafetyStop::kLocalizationLost);
}

}  // namespace
}  // namespace fleetnav::agent
