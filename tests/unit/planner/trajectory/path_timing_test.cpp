#include "fleetnav/planner/trajectory/path_timing.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/robot_model.hpp"

namespace fleetnav::planner {
namespace {

double AngleDiff(double a, double b) { return std::remainder(a - b, 2.0 * kPi); }

PathResult Path(const std::vector<Pose2>& poses) {
  PathResult r;
  r.poses = poses;
  return r;
}

// Time never runs back, speed, acceleration and yaw rate stay within the limits (tolerance
// 1e-6 relative), and the robot moves no faster between samples than its speeds allow.
void ExpectWithinLimits(const Trajectory& t, const MotionLimits& limits) {
  ASSERT_GE(t.points.size(), 2u);
  EXPECT_EQ(t.points.front().speed_mps, 0.0);
  EXPECT_EQ(t.points.back().speed_mps, 0.0);
  const double tol = 1.0 + 1e-6;
  for (size_t i = 1; i < t.points.size(); ++i) {
    const TrajectoryPoint& a = t.points[i - 1];
    const TrajectoryPoint& b = t.points[i];
    const double dt = b.t_s - a.t_s;
    ASSERT_GT(dt, 0.0) << "sample " << i;
    const double v_max = std::max(limits.max_speed_mps, limits.max_reverse_speed_mps);
    EXPECT_LE(b.speed_mps, v_max * tol) << "sample " << i;
    EXPECT_LE(std::abs(b.speed_mps - a.speed_mps) / dt, limits.max_accel_mps2 * tol + 1e-9)
        << "sample " << i;
    EXPECT_LE(std::abs(AngleDiff(b.yaw_rad, a.yaw_rad)) / dt, limits.max_yaw_rate_radps * tol)
        << "sample " << i;
    const double ds = (b.position_m - a.position_m).norm();
    EXPECT_LE(ds, 0.5 * (a.speed_mps + b.speed_mps) * dt * tol + 1e-9) << "sample " << i;
  }
}

TEST(PathTimingTest, LelyStopsToTurnInPlaceAndNeverReverses) {
  const RobotModel lely = RobotModelByKind("lely-vector").value();
  const Trajectory t =
      TimePath(Path({Pose2(0, 0, 0), Pose2(2, 0, 0), Pose2(2, 0, kPi / 2), Pose2(2, 1, kPi / 2)}),
               lely)
          .value();
  ExpectWithinLimits(t, lely.limits);
  bool stopped_at_corner = false;
  for (const TrajectoryPoint& p : t.points) {
    if ((p.position_m - Eigen::Vector2d(2, 0)).norm() < 1e-9) {
      stopped_at_corner |= p.speed_mps == 0.0;
    }
    if (p.speed_mps > 0.0) {
      EXPECT_NEAR(AngleDiff(p.heading_rad, p.yaw_rad), 0.0, 1e-12);
    }
  }
  EXPECT_TRUE(stopped_at_corner);
  EXPECT_NEAR(t.points.back().position_m.x(), 2.0, 1e-9);
  EXPECT_NEAR(t.points.back().position_m.y(), 1.0, 1e-9);
  EXPECT_NEAR(AngleDiff(t.points.back().yaw_rad, kPi / 2), 0.0, 1e-9);
  // At least the time of the distance at top speed plus the turn at top yaw rate.
  const double lower = 3.0 / lely.limits.max_speed_mps + (kPi / 2) / lely.limits.max_yaw_rate_radps;
  EXPECT_GT(t.points.back().t_s, lower);
}

TEST(PathTimingTest, AckermannSlowsOnTheArcAndStopsToReverse) {
  const RobotModel car = RobotModelByKind("ackermann-delivery").value();
  const double radius = car.wheelbase_m / std::tan(car.limits.max_steering_rad);
  const Pose2 end_of_arc(radius, radius, kPi / 2);
  const Trajectory t =
      TimePath(Path({Pose2(0, 0, 0), end_of_arc, Pose2(radius, radius - 1.0, kPi / 2)}), car)
          .value();
  ExpectWithinLimits(t, car.limits);
  bool stopped_to_reverse = false, reversed = false;
  for (const TrajectoryPoint& p : t.points) {
    if ((p.position_m - end_of_arc.translation()).norm() < 1e-9) {
      stopped_to_reverse |= p.speed_mps == 0.0;
    }
    if (p.speed_mps > 0.0 && std::abs(AngleDiff(p.heading_rad, p.yaw_rad + kPi)) < 1e-9) {
      reversed = true;
      EXPECT_LE(p.speed_mps, car.limits.max_reverse_speed_mps * (1 + 1e-9));
    }
  }
  EXPECT_TRUE(stopped_to_reverse);
  EXPECT_TRUE(reversed);
  // The arc really is an arc of the turning radius: every sample on it is `radius` from the
  // centre (0, radius).
  for (const TrajectoryPoint& p : t.points) {
    if (p.position_m.y() < radius - 1e-9 && p.position_m.x() < radius - 1e-9 &&
        p.position_m.x() > 1e-9) {
      EXPECT_NEAR((p.position_m - Eigen::Vector2d(0, radius)).norm(), radius, 1e-9);
    }
  }
}

TEST(PathTimingTest, RejectsWhatItCannotTime) {
  const RobotModel lely = RobotModelByKind("lely-vector").value();
  absl::Status backwards = TimePath(Path({Pose2(1, 0, 0), Pose2(0, 0, 0)}), lely).status();
  EXPECT_EQ(backwards.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(backwards.message().find("path.poses[0]"), std::string::npos) << backwards;
  EXPECT_EQ(TimePath(Path({Pose2()}), lely).status().code(), absl::StatusCode::kInvalidArgument);
  const RobotModel omni = RobotModelByKind("mecanum-platform").value();
  EXPECT_EQ(TimePath(Path({Pose2(), Pose2(1, 0, 0)}), omni).status().code(),
            absl::StatusCode::kInvalidArgument);
  PathTimingParams bad;
  bad.sample_spacing_m = 0.0;
  EXPECT_EQ(TimePath(Path({Pose2(), Pose2(1, 0, 0)}), lely, bad).status().code(),
            absl::StatusCode::kInvalidArgument);
}

class PlannedTrajectoryTest : public ::testing::TestWithParam<std::string> {};

// Every robot kind: a planner path around a box becomes a timed trajectory within the limits.
TEST_P(PlannedTrajectoryTest, EveryKindGetsATimedTrajectoryOfItsPlannedPath) {
  const RobotModel model = RobotModelByKind(GetParam()).value();
  OccupancyGrid grid =
      OccupancyGrid::Filled(150, 150, 0.1, Pose2(), OccupancyGrid::kFreeValue).value();
  for (int y = 40; y < 110; ++y) {
    for (int x = 70; x < 80; ++x) grid.SetValue({x, y}, OccupancyGrid::kOccupiedValue);
  }
  CostmapParams cp;
  cp.padding_m = 0.08;
  Costmap costmap = Costmap::Build(grid, model.footprint_m, cp).value();
  std::unique_ptr<SingleRobotPlanner> planner =
      MakeSingleRobotPlanner(&costmap, model, LatticeParams{}).value();
  PathRequest request;
  request.start = Pose2(3.0, 7.5, 0.0);
  request.goal = Pose2(12.0, 7.5, 0.0);
  request.time_limit_s = 5.0;
  const PathResult path = planner->Plan(request).value();
  absl::StatusOr<Trajectory> t = TrajectoryForPath(path, &costmap, model);
  ASSERT_TRUE(t.ok()) << t.status();
  ExpectWithinLimits(*t, model.limits);
  EXPECT_NEAR((t->points.back().position_m - path.poses.back().translation()).norm(), 0.0, 1e-6);
}

INSTANTIATE_TEST_SUITE_P(AllKinds, PlannedTrajectoryTest,
                         ::testing::Values("lely-vector", "mecanum-platform", "ackermann-delivery"),
                         [](const auto& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

}  // namespace
}  // namespace fleetnav::planner
