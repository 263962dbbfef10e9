#include "fleetnav/planner/coordination/route_segments.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "fleetnav/core/angles.hpp"

namespace fleetnav::planner {
namespace {

/// A predicted action along `length_m` east then as far north, in 0.1 m poses, 1 s per metre.
PredictedAction Corner(double length_m) {
  PredictedAction action;
  for (double x = 0.0; x <= length_m + 1e-9; x += 0.1) action.poses.emplace_back(x, 0.0, 0.0);
  for (double y = 0.1; y <= length_m + 1e-9; y += 0.1) {
    action.poses.emplace_back(length_m, y, kPi / 2);
  }
  action.duration_s = 2.0 * length_m;
  return action;
}

TEST(RouteSegmentsTest, AnActionIsCutIntoSegmentsThatChainWithGatesAlongTheWay) {
  const PredictedAction action = Corner(5.0);  // 10 m
  const std::vector<ActionSegment> segments = SplitIntoSegments(action, 1.5);
  ASSERT_EQ(segments.size(), 7u);  // 1.5 m each, the last 1 m (at least half a segment)
  double duration_s = 0.0;
  for (size_t j = 0; j < segments.size(); ++j) {
    duration_s += segments[j].duration_s;
    if (j > 0) {
      EXPECT_TRUE(segments[j].poses.front().IsNear(segments[j - 1].poses.back(), 1e-12, 1e-12));
    }
    EXPECT_EQ(segments[j].gate.has_value(), j + 1 < segments.size()) << j;
  }
  EXPECT_NEAR(duration_s, action.duration_s, 1e-9);
  EXPECT_TRUE(segments.back().poses.back().IsNear(action.poses.back(), 1e-12, 1e-12));
  // The first gate is 1.5 m east, facing east; the fifth is on the northward leg, facing north.
  EXPECT_NEAR(segments[0].gate->x_m(), 1.5, 0.11);
  EXPECT_NEAR(segments[0].gate->yaw_rad(), 0.0, 1e-6);
  EXPECT_NEAR(segments[4].gate->x_m(), 5.0, 1e-9);
  EXPECT_NEAR(segments[4].gate->yaw_rad(), kPi / 2, 1e-6);
}

// A robot stepping aside stands at a place on its way until it is cleared on: a segment ends
// where the way comes nearest that place, in a short action too.
TEST(RouteSegmentsTest, ASegmentEndsWhereTheWayComesNearestEachStop) {
  const PredictedAction action = Corner(5.0);
  const std::vector<ActionSegment> segments =
      SplitIntoSegments(action, 1.5, {Eigen::Vector2d(2.23, 0.3)});
  const auto gate_near = [&](double x_m, double y_m) {
    return std::any_of(segments.begin(), segments.end(), [&](const ActionSegment& s) {
      return s.gate && std::hypot(s.gate->x_m() - x_m, s.gate->y_m() - y_m) < 0.06;
    });
  };
  EXPECT_TRUE(gate_near(2.2, 0.0));
  const PredictedAction short_action = Corner(1.0);  // 2 m: one segment without stops
  ASSERT_EQ(SplitIntoSegments(short_action, 1.5).size(), 1u);
  const std::vector<ActionSegment> stopped =
      SplitIntoSegments(short_action, 1.5, {Eigen::Vector2d(1.0, 0.0)});
  ASSERT_EQ(stopped.size(), 2u);
  EXPECT_NEAR(stopped[0].gate->x_m(), 1.0, 1e-9);
  EXPECT_NEAR(stopped[0].gate->y_m(), 0.0, 1e-9);
  EXPECT_NEAR(stopped[0].duration_s + stopped[1].duration_s, short_action.duration_s, 1e-9);
  // Whole actions (no segments) ignore stops.
  EXPECT_EQ(SplitIntoSegments(short_action, 0.0, {Eigen::Vector2d(1.0, 0.0)}).size(), 1u);
}

TEST(RouteSegmentsTest, ShortActionsTurnsAndWholeActionOrderingAreOneSegment) {
  EXPECT_EQ(SplitIntoSegments(Corner(0.6), 1.5).size(), 1u);  // 1.2 m
  PredictedAction turn;
  for (int i = 0; i <= 10; ++i) turn.poses.emplace_back(1.0, 1.0, 0.15 * i);
  EXPECT_EQ(SplitIntoSegments(turn, 1.5).size(), 1u);
  EXPECT_EQ(SplitIntoSegments(Corner(5.0), 0.0).size(), 1u);
}

}  // namespace
}  // namespace fleetnav::planner
