// Conformance suite: every single-robot planner (one per kinematics kind) on the same maps:
// collision-free for the footprint, start and goal within tolerance, kinematics respected.
#include "fleetnav/planner/single_robot/single_robot_planner.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/planner/single_robot/planner_factory.hpp"
#include "test_maps.hpp"

namespace fleetnav::planner {
namespace {

double AngleDiff(double a, double b) { return std::remainder(a - b, 2.0 * kPi); }

using testing::DoorGrid;

struct Case {
  const char* name;
  RobotModel (*model)();
  PlannerKind kind;
  int seeds;  // stochastic planners run over seeds 1..seeds
};

// Checks one returned path: starts at the start, ends within the goal tolerance, collision-free
// for the footprint (every segment sampled so that no footprint point moves more than a quarter
// cell between checks) and kinematically valid for the model.
void ExpectValidPath(const std::string& label, const RobotModel& model, Costmap& checker,
                     const PathRequest& req, const PathResult& r) {
  ASSERT_GE(r.poses.size(), 2u) << label;
  EXPECT_TRUE(r.poses.front().IsNear(req.start, 1e-9, 1e-9)) << label;
  const Pose2& end = r.poses.back();
  EXPECT_LE((end.translation() - req.goal.translation()).norm(), req.goal_tolerance_m) << label;
  EXPECT_LE(std::abs(AngleDiff(end.yaw_rad(), req.goal.yaw_rad())), req.goal_tolerance_rad)
      << label;
  const double step_m = 0.25 * checker.resolution_m();
  for (size_t i = 1; i < r.poses.size(); ++i) {
    const Pose2& a = r.poses[i - 1];
    const Pose2& b = r.poses[i];
    const Eigen::Vector2d d = b.translation() - a.translation();
    const double dyaw = AngleDiff(b.yaw_rad(), a.yaw_rad());
    // Collision: sample the segment densely (position and yaw interpolated).
    const double sweep_m = d.norm() + std::abs(dyaw) * checker.circumscribed_radius_m();
    const int samples = std::max(1, static_cast<int>(std::ceil(sweep_m / step_m)));
    for (int k = 0; k <= samples; ++k) {
      const double f = static_cast<double>(k) / samples;
      ASSERT_TRUE(
          checker.PoseFree(a.x_m() + f * d.x(), a.y_m() + f * d.y(), a.yaw_rad() + f * dyaw))
          << label << " collides near pose " << i;
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
        ASSERT_GT(d.norm(), 1e-9) << label << ": Ackermann cannot turn in place";
        const double radius = model.wheelbase_m / std::tan(model.limits.max_steering_rad);
        // The turn over a chord c is at most 2·asin(c / 2R): curvature ≤ 1 / R.
        EXPECT_LE(std::abs(dyaw), 2.0 * std::asin(std::min(1.0, d.norm() / (2 * radius))) + 1e-9)
            << label << " at pose " << i;
        // No sideways motion: the chord of an arc (or a straight) points along the mean heading,
        // forward or, when the model may reverse, backward.
        const double mid = a.yaw_rad() + 0.5 * dyaw;
        const double off = AngleDiff(std::atan2(d.y(), d.x()), mid);
        const bool forward = std::abs(off) < 1e-6;
        const bool backward = std::abs(std::abs(off) - kPi) < 1e-6;
        EXPECT_TRUE(forward || (backward && model.limits.max_reverse_speed_mps > 0.0))
            << label << " moves sideways at pose " << i << " (" << off << " rad)";
        break;
      }
      case Kinematics::kOmnidirectional:
        EXPECT_TRUE(d.allFinite());
        break;
    }
  }
}

class PlannerConformanceTest : public ::testing::TestWithParam<Case> {};

TEST_P(PlannerConformanceTest, CollisionFreeWithinToleranceAndKinematicallyValid) {
  const RobotModel model = GetParam().model();
  CostmapParams cp;
  cp.padding_m = 0.08;  // covers the half-cell snapping and the yaw-bin error
  absl::StatusOr<Costmap> costmap = Costmap::Build(DoorGrid(), model.footprint_m, cp);
  ASSERT_TRUE(costmap.ok()) << costmap.status();
  // An unpadded costmap checks the result independently of the planner's own checks.
  absl::StatusOr<Costmap> checker = Costmap::Build(DoorGrid(), model.footprint_m, CostmapParams{});
  ASSERT_TRUE(checker.ok());

  const std::vector<std::pair<Pose2, Pose2>> requests = {
      {Pose2(5.0, 8.0, 0.0), Pose2(19.0, 8.0, 0.0)},        // through the door
      {Pose2(5.0, 5.0, kPi), Pose2(19.0, 11.0, kPi / 2)},   // starts facing away
      {Pose2(19.0, 12.0, -kPi / 2), Pose2(4.0, 4.0, kPi)},  // back again
      {Pose2(3.0, 13.5, 0.0), Pose2(21.0, 13.5, 0.0)},      // round the wall
  };
  int exact = 0, runs = 0;
  for (int seed = 1; seed <= GetParam().seeds; ++seed) {
    SingleRobotPlannerParams params;
    params.kind = GetParam().kind;
    params.ompl.seed = static_cast<uint32_t>(seed);
    absl::StatusOr<std::unique_ptr<SingleRobotPlanner>> planner =
        MakeSingleRobotPlanner(&*costmap, model, params);
    ASSERT_TRUE(planner.ok()) << planner.status();
    for (const auto& [start, goal] : requests) {
      PathRequest req;
      req.start = start;
      req.goal = goal;
      req.time_limit_s = GetParam().seeds > 1 ? 2.0 : 20.0;
      absl::StatusOr<PathResult> r = (*planner)->Plan(req);
      ASSERT_TRUE(r.ok()) << r.status();
      ++runs;
      if (!r->exact) continue;  // counted below; approximate paths are not checked for the goal
      ++exact;
      ExpectValidPath(absl::StrCat(GetParam().name, " seed ", seed), model, *checker, req, *r);
    }
  }
  // Deterministic planners solve every request; stochastic ones at least 9 in 10.
  if (GetParam().seeds == 1) {
    EXPECT_EQ(exact, runs) << GetParam().name;
  } else {
    EXPECT_GE(exact, (9 * runs + 9) / 10) << GetParam().name << ": " << exact << "/" << runs;
  }
}

INSTANTIATE_TEST_SUITE_P(
    AllPlanners, PlannerConformanceTest,
    ::testing::Values(Case{"lely", &LelyVectorModel, PlannerKind::kLattice, 1},
                      Case{"mecanum", &MecanumPlatformModel, PlannerKind::kLattice, 1},
                      Case{"ackermann", &AckermannDeliveryModel, PlannerKind::kLattice, 1},
                      Case{"ompl_omni", &MecanumPlatformModel, PlannerKind::kOmplOmni, 10},
                      Case{"ompl_reeds_shepp", &AckermannDeliveryModel,
                           PlannerKind::kOmplReedsShepp, 10}),
    [](const ::testing::TestParamInfo<Case>& info) { return std::string(info.param.name); });

TEST(LatticePlannerTest, EnclosedGoalGivesAnApproximatePathOrNotFound) {
  OccupancyGrid grid = DoorGrid();
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
  absl::StatusOr<Costmap> costmap = Costmap::Build(DoorGrid(), model.footprint_m, CostmapParams{});
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
