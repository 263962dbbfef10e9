#include "fleetnav/robot_agent/stop_guard.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace fleetnav::agent {
namespace {

/// A stop of zone `pen` of map `barn`: the square x, y in [0, 2].
RobotStop PenStop() {
  RobotStop stop;
  stop.map_id = "barn";
  stop.zone = "pen";
  stop.polygon_in_map = {{0.0, 0.0}, {2.0, 0.0}, {2.0, 2.0}, {0.0, 2.0}};
  return stop;
}

TEST(StopGuardTest, NearingAStoppedZoneIsSlowedToWhatBrakesBeforeItsReachMeetsTheZone) {
  const std::vector<RobotStop> stops = {PenStop()};
  // 1.5 m west of the pen, heading east at 1 m/s, reach 0.6 m: 0.9 m left to brake in.
  const Pose2 west(-1.5, 1.0, 0.0);
  const Twist2 east{1.0, 0.0, 0.2};
  const Twist2 slowed = KeepOffStoppedZones(east, stops, "barn", west, 0.6, 0.4);
  EXPECT_NEAR(slowed.vx_mps, std::sqrt(2.0 * 0.4 * 0.9), 1e-9);
  EXPECT_NEAR(slowed.yaw_rate_radps / slowed.vx_mps, 0.2, 1e-9);  // the same curvature
  // With nothing left: standing. Sideways (a mecanum platform), along the edge: as it is.
  const Pose2 at_reach(-0.6, 1.0, 0.0);
  EXPECT_EQ(KeepOffStoppedZones(east, stops, "barn", at_reach, 0.6, 0.4).vx_mps, 0.0);
  const Twist2 along{0.0, 0.8, 0.0};
  EXPECT_EQ(KeepOffStoppedZones(along, stops, "barn", at_reach, 0.6, 0.4).vy_mps, 0.8);
  const Twist2 away{-0.8, 0.0, 0.0};
  EXPECT_EQ(KeepOffStoppedZones(away, stops, "barn", at_reach, 0.6, 0.4).vx_mps, -0.8);
  // Another map's stop, or none: as it is.
  EXPECT_EQ(KeepOffStoppedZones(east, stops, "store", at_reach, 0.6, 0.4).vx_mps, 1.0);
}

TEST(StopGuardTest, ARobotDrivingAtAStoppedZoneStandsBeforeItsReachMeetsIt) {
  const std::vector<RobotStop> stops = {PenStop()};
  // Heading north-east at the pen's corner region from the south-west, 1 m/s commanded
  // every 20 ms, the drive following the command at once.
  Pose2 pose(-3.0, -2.0, std::atan2(2.5, 3.5));
  const double reach_m = 0.6;
  double closest_m = 1e9;
  for (int tick = 0; tick < 1000; ++tick) {
    const Twist2 command = KeepOffStoppedZones({1.0, 0.0, 0.0}, stops, "barn", pose, reach_m, 0.4);
    pose = Pose2(pose.x_m() + 0.02 * command.vx_mps * std::cos(pose.yaw_rad()),
                 pose.y_m() + 0.02 * command.vx_mps * std::sin(pose.yaw_rad()), pose.yaw_rad());
    closest_m =
        std::min(closest_m, DistanceToPolygonBoundary(stops[0].polygon_in_map, pose.translation()));
  }
  EXPECT_FALSE(PolygonContains(stops[0].polygon_in_map, pose.translation()));
  EXPECT_GT(closest_m, reach_m - 0.02);  // at most one tick's creep past the reach
  EXPECT_LT(closest_m, reach_m + 0.05);  // and it came up to it
}

}  // namespace
}  // namespace fleetnav::agent
