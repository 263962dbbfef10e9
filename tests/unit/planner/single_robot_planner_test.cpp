// Conformance suite: every single-robot planner (one per kinematics kind) on the same maps:
// collision-free for the footprint, start and goal within tolerance, kinematics respected.
#include "fleetnav/planner/single_robot_planner.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "fleetnav/core/robot_model.hpp"

namespace fleetnav::planner {
namespace {

double AngleDiff(double a, double b) { return std::remainder(a - b, 2.0 * M_PI); }

// 24 m × 16 m at 0.1 m: a wall at x = 12 m with a 4 m door, and a few boxes.
OccupancyGrid TestGrid() {
  OccupancyGrid grid =
      OccupancyGrid::Filled(240, 160, 0.1, Pose2(), OccupancyGrid::kFreeValue).value();
  for (int y = 0; y < 160; ++y) {
    for (int x = 0; x < 240; ++x) {
      const bool border = x < 2 || y < 2 || x >= 238 || y >= 158;
      const bool wall = x >= 118 && x < 122 && !(y >= 60 && y < 100);
      const bool box =
          (x >= 50 && x < 70 && y >= 100 && y < 120) || (x >= 170 && x < 185 && y >= 30 && y < 50);
      if (border || wall || box) grid.SetValue({x, y}, OccupancyGrid::kOccupiedValue);
    }
  }
  return grid;
}

struct Case {
  const char* name;
  RobotModel (*model)();
};

class PlannerConformanceTest : public ::testing::TestWithParam<Case> {};

TEST_P(PlannerConformanceTest, CollisionFreeWithinToleranceAndKinematicallyValid) {
  const RobotModel model = GetParam().model();
  CostmapParams cp;
  cp.padding_m = 0.08;  // covers the half-cell snapping and the yaw-bin error
  absl::StatusOr<Costmap> costmap = Costmap::Build(TestGrid(), model.footprint_m, cp);
  ASSERT_TRUE(costmap.ok()) << costmap.status();
  // An unpadded costmap checks the result independently of the planner's own checks.
  absl::StatusOr<Costmap> checker = Costmap::Build(TestGrid(), model.footprint_m, CostmapParams{});
  ASSERT_TRUE(checker.ok());
  absl::StatusOr<std::unique_ptr<SingleRobotPlanner>> planner =
      MakeSingleRobotPlanner(&*costmap, model, LatticeParams{});
  ASSERT_TRUE(planner.ok()) << planner.status();

  const std::vector<std::pair<Pose2, Pose2>> requests = {
      {Pose2(5.0, 8.0, 0.0), Pose2(19.0, 8.0, 0.0)},          // through the door
      {Pose2(5.0, 5.0, M_PI), Pose2(19.0, 11.0, M_PI / 2)},   // starts facing away
      {Pose2(19.0, 12.0, -M_PI / 2), Pose2(4.0, 4.0, M_PI)},  // back again
  };
  for (const auto& [start, goal] : requests) {
    PathRequest req;
    req.start = start;
    req.goal = goal;
    req.time_limit_s = 20.0;
    absl::StatusOr<PathResult> r = (*planner)->Plan(req);
    ASSERT_TRUE(r.ok()) << r.status();
    ASSERT_TRUE(r->exact) << GetParam().name;
    ASSERT_GE(r->poses.size(), 2u);
    EXPECT_TRUE(r->poses.front().IsNear(start, 1e-9, 1e-9));
    const Pose2& end = r->poses.back();
    EXPECT_LE((end.translation() - goal.translation()).norm(), req.goal_tolerance_m);
    EXPECT_LE(std::abs(AngleDiff(end.yaw_rad(), goal.yaw_rad())), req.goal_tolerance_rad);
    for (size_t i = 1; i < r->poses.size(); ++i) {
      const Pose2& a = r->poses[i - 1];
      const Pose2& b = r->poses[i];
      const Eigen::Vector2d d = b.translation() - a.translation();
      const double dyaw = AngleDiff(b.yaw_rad(), a.yaw_rad());
      // Collision: sample the segment densely (position and yaw interpolated).
      for (int k = 0; k <= 10; ++k) {
        const double f = k / 10.0;
        ASSERT_TRUE(
            checker->PoseFree(a.x_m() + f * d.x(), a.y_m() + f * d.y(), a.yaw_rad() + f * dyaw))
            << GetParam().name << " collides near pose " << i;
      }
      const Eigen::Vector2d heading(std::cos(a.yaw_rad()), std::sin(a.yaw_rad()));
      switch (model.kinematics) {
        case Kinematics::kDifferential:
          if (d.norm() > 1e-9) {
            EXPECT_NEAR(dyaw, 0.0, 1e-9);  // translate only straight ahead ...
            EXPECT_NEAR(std::abs(heading.dot(d)), d.norm(), 1e-9);
            if (model.limits.max_reverse_speed_mps == 0.0) {
              EXPECT_GT(heading.dot(d), 0.0) << "reverses at pose " << i;  // ... never back
            }
          }
          break;
        case Kinematics::kAckermann: {
          ASSERT_GT(d.norm(), 1e-9) << "Ackermann cannot turn in place";
          const double radius = model.wheelbase_m / std::tan(model.limits.max_steering_rad);
          // The turn over a chord c is at most 2·asin(c / 2R): curvature ≤ 1 / R.
          EXPECT_LE(std::abs(dyaw), 2.0 * std::asin(std::min(1.0, d.norm() / (2 * radius))) + 1e-9);
          break;
        }
        case Kinematics::kOmnidirectional:
          EXPECT_TRUE(d.allFinite());
          break;
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllKinds, PlannerConformanceTest,
                         ::testing::Values(Case{"lely", &LelyVectorModel},
                                           Case{"mecanum", &MecanumPlatformModel},
                                           Case{"ackermann", &AckermannDeliveryModel}),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           return std::string(info.param.name);
                         });

TEST(LatticePlannerTest, EnclosedGoalGivesAnApproximatePathOrNotFound) {
  OccupancyGrid grid = TestGrid();
  for (int x = 150; x < 238; ++x) {
    grid.SetValue({x, 60}, OccupancyGrid::kOccupiedValue);
    grid.SetValue({x, 61}, OccupancyGrid::kOccupiedValue);
  }
  for (int y = 2; y < 62; ++y) {
    grid.SetValue({150, y}, OccupancyGrid::kOccupiedValue);
    grid.SetValue({151, y}, OccupancyGrid::kOccupiedValue);
  }
  const RobotModel model = MecanumPlatformModel();
  absl::StatusOr<Costmap> costmap = Costmap::Build(grid, model.footprint_m, CostmapParams{});
  ASSERT_TRUE(costmap.ok());
  PathRequest req;
  req.start = Pose2(5.0, 8.0, 0.0);
  req.goal = Pose2(20.0, 3.0, 0.0);
  LatticeParams params;
  LatticePlanner approx(&*costmap, model, params);
  absl::StatusOr<PathResult> r = approx.Plan(req);
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_FALSE(r->exact);
  params.allow_approximate = false;
  LatticePlanner strict(&*costmap, model, params);
  EXPECT_EQ(strict.Plan(req).status().code(), absl::StatusCode::kNotFound);
}

TEST(LatticePlannerTest, RejectsStartInCollisionAndBadRequests) {
  const RobotModel model = LelyVectorModel();
  absl::StatusOr<Costmap> costmap = Costmap::Build(TestGrid(), model.footprint_m, CostmapParams{});
  ASSERT_TRUE(costmap.ok());
  LatticePlanner planner(&*costmap, model, LatticeParams{});
  PathRequest req;
  req.start = Pose2(12.0, 2.0, 0.0);  // inside the wall
  req.goal = Pose2(5.0, 8.0, 0.0);
  EXPECT_EQ(planner.Plan(req).status().code(), absl::StatusCode::kInvalidArgument);
  req.start = Pose2(5.0, 8.0, 0.0);
  req.goal_tolerance_m = 0.0;
  EXPECT_EQ(planner.Plan(req).status().code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fleetnav::planner
