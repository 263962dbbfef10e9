#include "fleetnav/robot_agent/control/common/path_geometry.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace fleetnav::agent {
namespace {

const std::vector<Pose2> kPath = {Pose2(0, 0, 0), Pose2(1, 0, 0), Pose2(1, 0, 1.0),
                                  Pose2(1, 2, 1.0)};

TEST(PathGeometryTest, DistancesToGoalCountTurnsInPlaceAsNothing) {
  EXPECT_EQ(DistancesToGoal(kPath), (std::vector<double>{3.0, 2.0, 2.0, 0.0}));
  EXPECT_TRUE(DistancesToGoal({}).empty());
}

TEST(PathGeometryTest, ClosestPoseIsSearchedInTheWindowFirstOnTies) {
  const ClosestPose near_turn = FindClosestPose(kPath, Pose2(1.1, 0.1, 0), 0, 4);
  EXPECT_EQ(near_turn.index, 1u);  // poses 1 and 2 are one place
  EXPECT_NEAR(near_turn.distance_m, std::hypot(0.1, 0.1), 1e-12);
  // Only [first, last) is looked at, and last may lie past the end.
  EXPECT_EQ(FindClosestPose(kPath, Pose2(0, 0, 0), 2, 100).index, 2u);
  EXPECT_EQ(FindClosestPose(kPath, Pose2(1, 2, 0), 0, 2).index, 1u);
}

}  // namespace
}  // namespace fleetnav::agent
