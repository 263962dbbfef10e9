#include "fleetnav/planner/trajectory/spline.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "fleetnav/core/angles.hpp"

namespace fleetnav::planner {
namespace {

TEST(CubicSplineTest, InterpolatesKnotsWithChordLengthParameters) {
  const std::vector<Eigen::Vector2d> knots = {{0, 0}, {3, 0}, {3, 4}, {6, 4}};
  absl::StatusOr<CubicSpline> s = CubicSpline::Create(knots, {1, 0}, {1, 0});
  ASSERT_TRUE(s.ok()) << s.status();
  const std::vector<double> expected = {0.0, 0.3, 0.7, 1.0};
  for (size_t i = 0; i < knots.size(); ++i) {
    EXPECT_NEAR(s->parameters()[i], expected[i], 1e-12);
    EXPECT_NEAR((s->Evaluate(s->parameters()[i]) - knots[i]).norm(), 0.0, 1e-9);
  }
}

TEST(CubicSplineTest, IsC2AtInteriorKnotsAndHonoursEndTangents) {
  const std::vector<Eigen::Vector2d> knots = {{0, 0}, {1, 2}, {3, 3}, {4, 1}, {6, 0}};
  const Eigen::Vector2d start_dir(0, 1), end_dir(1, -1);
  absl::StatusOr<CubicSpline> s = CubicSpline::Create(knots, start_dir, end_dir);
  ASSERT_TRUE(s.ok());
  const double eps = 1e-7;
  for (size_t i = 1; i + 1 < knots.size(); ++i) {
    const double u = s->parameters()[i];
    EXPECT_NEAR((s->Evaluate(u - eps) - s->Evaluate(u + eps)).norm(), 0.0, 1e-5);
    EXPECT_NEAR((s->Derivative(u - eps) - s->Derivative(u + eps)).norm(), 0.0, 1e-4);
    EXPECT_NEAR((s->SecondDerivative(u - eps) - s->SecondDerivative(u + eps)).norm(), 0.0, 1e-3)
        << "knot " << i;
  }
  const Eigen::Vector2d d0 = s->Derivative(0.0).normalized();
  const Eigen::Vector2d d1 = s->Derivative(1.0).normalized();
  EXPECT_NEAR(d0.dot(start_dir.normalized()), 1.0, 1e-9);
  EXPECT_NEAR(d1.dot(end_dir.normalized()), 1.0, 1e-9);
}

TEST(CubicSplineTest, RejectsRepeatedKnotsAndZeroTangents) {
  EXPECT_FALSE(CubicSpline::Create({{0, 0}, {0, 0}}, {1, 0}, {1, 0}).ok());
  EXPECT_FALSE(CubicSpline::Create({{0, 0}}, {1, 0}, {1, 0}).ok());
  EXPECT_FALSE(CubicSpline::Create({{0, 0}, {1, 0}}, {0, 0}, {1, 0}).ok());
}

// Largest change of travel direction between consecutive samples.
double MaxDirectionJump(const std::vector<Eigen::Vector2d>& pts) {
  double worst = 0.0;
  for (size_t i = 2; i < pts.size(); ++i) {
    const Eigen::Vector2d a = pts[i - 1] - pts[i - 2];
    const Eigen::Vector2d b = pts[i] - pts[i - 1];
    worst = std::max(worst, std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)));
  }
  return worst;
}

TEST(EndpointAugmentationTest, SidewaysAndBackNoLongerReversesOnTheSpot) {
  // The KUKA scanning motion: 1 m sideways and back.
  const std::vector<Eigen::Vector2d> knots = {{0, 0}, {0, 1}, {0, 0}};
  absl::StatusOr<CubicSpline> plain = CubicSpline::Create(knots, {0, 1}, {0, -1});
  ASSERT_TRUE(plain.ok());
  EXPECT_GT(MaxDirectionJump(plain->Sample(200)), kPi * 0.9);  // a 180° flip
  const std::vector<Eigen::Vector2d> augmented = AugmentEndpoints(knots, 0.2, kPi / 2);
  ASSERT_EQ(augmented.size(), 4u);
  EXPECT_EQ(augmented[1], knots[1]);  // the scan end point is still visited
  absl::StatusOr<CubicSpline> smooth = CubicSpline::Create(augmented, {0, 1}, {0, -1});
  ASSERT_TRUE(smooth.ok());
  EXPECT_LT(MaxDirectionJump(smooth->Sample(200)), 0.2);
  // Gentle corners are left alone.
  EXPECT_EQ(AugmentEndpoints({{0, 0}, {1, 0}, {2, 0.5}}, 0.2, kPi / 2).size(), 3u);
}

TEST(TimeParameterizeTest, RespectsSpeedYawRateAndAccelerationAndRestsAtTheEnds) {
  absl::StatusOr<CubicSpline> s =
      CubicSpline::Create({{0, 0}, {4, 0}, {5, 1}, {5, 5}}, {1, 0}, {0, 1});
  ASSERT_TRUE(s.ok());
  MotionLimits limits;
  limits.max_speed_mps = 0.8;
  limits.max_yaw_rate_radps = 0.5;
  limits.max_accel_mps2 = 0.4;
  const std::vector<Eigen::Vector2d> pts = s->Sample(50);
  absl::StatusOr<std::vector<TimedPose>> timed = TimeParameterize(pts, limits);
  ASSERT_TRUE(timed.ok()) << timed.status();
  EXPECT_DOUBLE_EQ(timed->front().speed_mps, 0.0);
  EXPECT_DOUBLE_EQ(timed->back().speed_mps, 0.0);
  for (size_t i = 1; i < timed->size(); ++i) {
    const TimedPose& a = (*timed)[i - 1];
    const TimedPose& b = (*timed)[i];
    ASSERT_GT(b.t_s, a.t_s);
    EXPECT_LE(b.speed_mps, limits.max_speed_mps + 1e-12);
    const double ds = (b.position_m - a.position_m).norm();
    // v² changes by at most 2 a ds.
    EXPECT_LE(std::abs(b.speed_mps * b.speed_mps - a.speed_mps * a.speed_mps),
              2 * limits.max_accel_mps2 * ds + 1e-9);
    if (i + 1 < timed->size()) {
      const Eigen::Vector2d c = (*timed)[i + 1].position_m;
      const double turn = std::abs(std::remainder(
          std::atan2(c.y() - b.position_m.y(), c.x() - b.position_m.x()) -
              std::atan2(b.position_m.y() - a.position_m.y(), b.position_m.x() - a.position_m.x()),
          2 * kPi));
      const double arc = 0.5 * (ds + (c - b.position_m).norm());
      EXPECT_LE(b.speed_mps * turn / arc, limits.max_yaw_rate_radps + 1e-9);
    }
  }
  MotionLimits bad = limits;
  bad.max_accel_mps2 = 0;
  EXPECT_EQ(TimeParameterize(pts, bad).status().code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fleetnav::planner
