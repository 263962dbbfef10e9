#include "fleetnav/planner/trajectory/path_smoothing.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/planner/single_robot/ompl_omni_planner.hpp"
#include "test_maps.hpp"

namespace fleetnav::planner {
namespace {

double AngleDiff(double a, double b) { return std::remainder(a - b, 2.0 * kPi); }

OccupancyGrid OpenGrid() {
  return OccupancyGrid::Filled(100, 100, 0.1, Pose2(), OccupancyGrid::kFreeValue).value();
}

Costmap Padded(const OccupancyGrid& grid, const RobotModel& model) {
  CostmapParams cp;
  cp.padding_m = 0.08;
  return Costmap::Build(grid, model.footprint_m, cp).value();
}

PathResult Path(const std::vector<Pose2>& poses) {
  PathResult r;
  r.poses = poses;
  return r;
}

// Largest change of the direction of travel between two consecutive steps where the robot
// moves (speed > 0 at the sample between them).
double MaxMovingHeadingJump(const Trajectory& t) {
  double worst = 0.0;
  for (size_t i = 1; i + 1 < t.points.size(); ++i) {
    const Eigen::Vector2d a = t.points[i].position_m - t.points[i - 1].position_m;
    const Eigen::Vector2d b = t.points[i + 1].position_m - t.points[i].position_m;
    if (a.norm() < 1e-12 || b.norm() < 1e-12 || t.points[i].speed_mps <= 0.0) continue;
    worst = std::max(worst, std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)));
  }
  return worst;
}

// Collision-free between samples (quarter-cell sweep), limits respected, heading continuous
// wherever the robot moves.
void ExpectValidTrajectory(const Trajectory& t, const MotionLimits& limits, Costmap& checker) {
  ASSERT_GE(t.points.size(), 2u);
  EXPECT_EQ(t.points.front().speed_mps, 0.0);
  EXPECT_EQ(t.points.back().speed_mps, 0.0);
  const double step_m = 0.25 * checker.resolution_m();
  for (size_t i = 1; i < t.points.size(); ++i) {
    const TrajectoryPoint& a = t.points[i - 1];
    const TrajectoryPoint& b = t.points[i];
    const Eigen::Vector2d d = b.position_m - a.position_m;
    const double ds = d.norm();
    const double dyaw = AngleDiff(b.yaw_rad, a.yaw_rad);
    const double dt = b.t_s - a.t_s;
    const int n = std::max(
        1, static_cast<int>(
               std::ceil((ds + std::abs(dyaw) * checker.circumscribed_radius_m()) / step_m)));
    for (int k = 0; k <= n; ++k) {
      const double f = static_cast<double>(k) / n;
      const Eigen::Vector2d p = a.position_m + f * d;
      ASSERT_TRUE(checker.PoseFree(p.x(), p.y(), a.yaw_rad + f * dyaw)) << "collides at " << i;
    }
    if (ds > 1e-12 || std::abs(dyaw) > 1e-12) {
      ASSERT_GT(dt, 0.0) << i;
    }
    EXPECT_LE(b.speed_mps, limits.max_speed_mps + 1e-9);
    EXPECT_LE(std::abs(b.speed_mps * b.speed_mps - a.speed_mps * a.speed_mps),
              2.0 * limits.max_accel_mps2 * ds + 1e-9)
        << i;
    EXPECT_LE(std::abs(dyaw), limits.max_yaw_rate_radps * dt + 1e-9)
        << "platform yaw rate at " << i;
    if (i + 1 < t.points.size()) {
      const Eigen::Vector2d e = t.points[i + 1].position_m - b.position_m;
      if (ds > 1e-12 && e.norm() > 1e-12) {
        const double turn = std::acos(std::clamp(d.normalized().dot(e.normalized()), -1.0, 1.0));
        const double arc = 0.5 * (ds + e.norm());
        EXPECT_LE(b.speed_mps * turn / arc, limits.max_yaw_rate_radps + 1e-6)
            << "direction-of-travel rate at " << i;
      }
    }
  }
  // Where the robot moves, the direction of travel turns at most at the yaw rate (above) and by
  // less than 1 rad between samples ≤ 5 cm apart: no instantaneous reversal. Sharper corners
  // happen at rest only.
  EXPECT_LT(MaxMovingHeadingJump(t), 1.0);
}

TEST(SmoothPathTest, SidewaysAndBackBendsRoundInsteadOfReversing) {
  const RobotModel model = MecanumPlatformModel();
  Costmap costmap = Padded(OpenGrid(), model);
  Costmap checker = Costmap::Build(OpenGrid(), model.footprint_m, CostmapParams{}).value();
  // The KUKA scanning motion: 1 m sideways and back at a constant yaw.
  const PathResult path = Path({Pose2(5, 4, 0), Pose2(5, 5, 0), Pose2(5, 4, 0)});
  absl::StatusOr<Trajectory> t = SmoothPath(path, &costmap, model, SmoothingParams{});
  ASSERT_TRUE(t.ok()) << t.status();
  EXPECT_EQ(t->intervals, 2);
  EXPECT_EQ(t->raw_intervals, 0);
  ExpectValidTrajectory(*t, model.limits, checker);
  // The turn-back point is still visited, and the robot never stops there.
  const auto visit = std::find_if(t->points.begin(), t->points.end(), [](const TrajectoryPoint& p) {
    return (p.position_m - Eigen::Vector2d(5, 5)).norm() < 1e-9;
  });
  ASSERT_NE(visit, t->points.end());
  EXPECT_GT(visit->speed_mps, 0.0);
  EXPECT_NEAR((t->points.back().position_m - Eigen::Vector2d(5, 4)).norm(), 0.0, 1e-9);
  // Without the augmentation the same spline flips its direction by ~180° at one sample.
  SmoothingParams plain;
  plain.augment_max_turn_rad = kPi;
  absl::StatusOr<Trajectory> flip = SmoothPath(path, &costmap, model, plain);
  ASSERT_TRUE(flip.ok());
  EXPECT_GT(MaxMovingHeadingJump(*flip), 2.5);
}

TEST(SmoothPathTest, PlannedOmniPathsStayCollisionFreeWithinLimits) {
  const RobotModel model = MecanumPlatformModel();
  Costmap costmap = Padded(testing::DoorGrid(), model);
  Costmap checker = Costmap::Build(testing::DoorGrid(), model.footprint_m, CostmapParams{}).value();
  PathRequest req;
  req.start = Pose2(3.0, 14.5, 0.0);
  req.goal = Pose2(21.0, 14.5, kPi / 2);
  req.time_limit_s = 5.0;
  for (uint32_t seed = 1; seed <= 5; ++seed) {
    OmplPlannerParams params;
    params.seed = seed;
    OmplOmniPlanner planner(&costmap, params);
    absl::StatusOr<PathResult> path = planner.Plan(req);
    ASSERT_TRUE(path.ok()) << path.status();
    absl::StatusOr<Trajectory> t = SmoothPath(*path, &costmap, model, SmoothingParams{});
    ASSERT_TRUE(t.ok()) << t.status();
    SCOPED_TRACE(::testing::Message() << "seed " << seed << ", " << t->raw_intervals << "/"
                                      << t->intervals << " intervals straight");
    ExpectValidTrajectory(*t, model.limits, checker);
    EXPECT_TRUE(t->points.front().position_m.isApprox(req.start.translation()));
    EXPECT_NEAR((t->points.back().position_m - req.goal.translation()).norm(), 0.0, 1e-9);
    EXPECT_NEAR(AngleDiff(t->points.back().yaw_rad, path->poses.back().yaw_rad()), 0.0, 1e-9);
  }
  // The lattice's omni paths turn in place between straight moves.
  absl::StatusOr<std::unique_ptr<SingleRobotPlanner>> lattice =
      MakeSingleRobotPlanner(&costmap, model, LatticeParams{});
  ASSERT_TRUE(lattice.ok());
  absl::StatusOr<PathResult> path = (*lattice)->Plan(req);
  ASSERT_TRUE(path.ok()) << path.status();
  absl::StatusOr<Trajectory> t = SmoothPath(*path, &costmap, model, SmoothingParams{});
  ASSERT_TRUE(t.ok()) << t.status();
  ExpectValidTrajectory(*t, model.limits, checker);
}

TEST(SmoothPathTest, FallsBackToTheStraightSegmentWhereTheSplineCollides) {
  // A 1.2 m wide L-shaped corridor: the spline through its corner would cut or overshoot it.
  OccupancyGrid grid =
      OccupancyGrid::Filled(100, 100, 0.1, Pose2(), OccupancyGrid::kOccupiedValue).value();
  for (int y = 0; y < 100; ++y) {
    for (int x = 0; x < 100; ++x) {
      const bool leg1 = x >= 14 && x < 86 && y >= 14 && y < 26;
      const bool leg2 = x >= 74 && x < 86 && y >= 14 && y < 86;
      if (leg1 || leg2) grid.SetValue({x, y}, OccupancyGrid::kFreeValue);
    }
  }
  const RobotModel model = MecanumPlatformModel();
  Costmap costmap = Padded(grid, model);
  Costmap checker = Costmap::Build(grid, model.footprint_m, CostmapParams{}).value();
  const PathResult path = Path({Pose2(2.5, 2.0, 0), Pose2(8.0, 2.0, 0), Pose2(8.0, 7.5, 0)});
  for (const Pose2& p : path.poses) ASSERT_TRUE(costmap.PoseFree(p.x_m(), p.y_m(), 0.0));
  absl::StatusOr<Trajectory> t = SmoothPath(path, &costmap, model, SmoothingParams{});
  ASSERT_TRUE(t.ok()) << t.status();
  EXPECT_EQ(t->raw_intervals, 2) << "both legs near the corner leave the corridor";
  ExpectValidTrajectory(*t, model.limits, checker);
  // Two straight legs meet at a right angle: the corner is passed at rest.
  const auto corner = std::find_if(t->points.begin(), t->points.end(), [](const auto& p) {
    return (p.position_m - Eigen::Vector2d(8, 2)).norm() < 1e-9;
  });
  ASSERT_NE(corner, t->points.end());
  EXPECT_EQ(corner->speed_mps, 0.0);
}

TEST(SmoothPathTest, TurnInPlaceOnlyTakesTheYawRateTime) {
  const RobotModel model = MecanumPlatformModel();
  Costmap costmap = Padded(OpenGrid(), model);
  absl::StatusOr<Trajectory> t =
      SmoothPath(Path({Pose2(5, 5, 0), Pose2(5, 5, 1.0)}), &costmap, model, SmoothingParams{});
  ASSERT_TRUE(t.ok()) << t.status();
  EXPECT_EQ(t->intervals, 0);
  EXPECT_NEAR(t->points.back().yaw_rad, 1.0, 1e-12);
  EXPECT_NEAR(t->points.back().t_s, 1.0 / model.limits.max_yaw_rate_radps, 1e-9);
  for (const TrajectoryPoint& p : t->points) EXPECT_EQ(p.speed_mps, 0.0);
}

TEST(SmoothPathTest, RejectsBadInput) {
  const RobotModel omni = MecanumPlatformModel();
  Costmap costmap = Padded(OpenGrid(), omni);
  const PathResult path = Path({Pose2(5, 4, 0), Pose2(5, 5, 0)});
  EXPECT_EQ(SmoothPath(path, &costmap, LelyVectorModel(), SmoothingParams{}).status().code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(SmoothPath(PathResult{}, &costmap, omni, SmoothingParams{}).status().code(),
            absl::StatusCode::kInvalidArgument);
  SmoothingParams bad;
  bad.augment_radius_m = 0.0;
  absl::Status s = SmoothPath(path, &costmap, omni, bad).status();
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("augment_radius_m"), std::string::npos) << s;
}

}  // namespace
}  // namespace fleetnav::planner
