#include "fleetnav/core/segment_gate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

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
  EXPECT_FALSE(ReachedGate(gate, {-0.5, 0.0}));   // still before it
  EXPECT_FALSE(ReachedGate(gate, {0.5, 2.0}));    // past the line, but elsewhere
  EXPECT_TRUE(ReachedGate(gate, {-0.25, -0.1}));  // beside its point, where a path turns back
}

/// Poses every 0.05 m from `from` to `to`.
std::vector<Pose2> Line(const Eigen::Vector2d& from, const Eigen::Vector2d& to) {
  const Eigen::Vector2d d = to - from;
  const int n = static_cast<int>(std::ceil(d.norm() / 0.05));
  std::vector<Pose2> poses;
  for (int i = 0; i <= n; ++i) {
    const Eigen::Vector2d p = from + d * (static_cast<double>(i) / n);
    poses.emplace_back(p.x(), p.y(), std::atan2(d.y(), d.x()));
  }
  return poses;
}

TEST(SegmentGateTest, AlongAPathTheRobotStandsJustShortOfTheLineItCrosses) {
  const Pose2 gate(0.0, 0.0, 0.0);
  const std::vector<Pose2> east = Line({-3.0, 0.2}, {2.0, 0.2});
  const std::optional<double> along = PathDistanceToGate(gate, east);
  ASSERT_TRUE(along.has_value());
  EXPECT_NEAR(*along, 2.9, 1e-9);  // 0.1 m short of x = 0
  // Standing there, or beyond the line beside the point: it stands.
  EXPECT_NEAR(*PathDistanceToGate(gate, Line({-0.05, 0.2}, {2.0, 0.2})), 0.0, 1e-12);
  // A path that crosses the line far from the point does not come to the gate.
  EXPECT_FALSE(PathDistanceToGate(gate, Line({-3.0, 3.0}, {2.0, 3.0})).has_value());
}

TEST(SegmentGateTest, APathThatTurnsBackJustBeforeTheGateStandsWhereItComesClosest) {
  // Its heading points away from the gate's direction from the turn on, so a test of the
  // heading would let it drive on back past whoever waits for it to stand there.
  const Pose2 gate(0.0, 0.0, 0.0);
  std::vector<Pose2> path = Line({-3.0, 0.0}, {-0.2, 0.1});
  const std::vector<Pose2> back = Line({-0.2, 0.1}, {-3.0, 1.5});
  path.insert(path.end(), back.begin() + 1, back.end());
  const std::optional<double> along = PathDistanceToGate(gate, path);
  ASSERT_TRUE(along.has_value());
  EXPECT_NEAR(*along, (Eigen::Vector2d(-0.2, 0.1) - Eigen::Vector2d(-3.0, 0.0)).norm(), 0.06);
  // Turning back further off its point, the path does not come to the gate.
  std::vector<Pose2> wide = Line({-3.0, 0.0}, {-0.6, 0.0});
  const std::vector<Pose2> wide_back = Line({-0.6, 0.0}, {-3.0, 1.5});
  wide.insert(wide.end(), wide_back.begin() + 1, wide_back.end());
  EXPECT_FALSE(PathDistanceToGate(gate, wide).has_value());
}

TEST(SegmentGateTest, AWayOutAndBackComesToAGateOfItsReturnOnlyOnTheReturn) {
  // Out east to x = 3 and back west; the gate is on the return leg, facing west at x = 1.
  const Pose2 gate(1.0, 0.0, kPi);
  std::vector<Pose2> path = Line({-2.0, 0.0}, {3.0, 0.0});
  const std::vector<Pose2> back = Line({3.0, 0.0}, {-2.0, 0.05});
  path.insert(path.end(), back.begin() + 1, back.end());
  const std::optional<double> along = PathDistanceToGate(gate, path);
  ASSERT_TRUE(along.has_value());
  EXPECT_NEAR(*along, 5.0 + 1.9, 0.01);  // not where the way out passes it
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
