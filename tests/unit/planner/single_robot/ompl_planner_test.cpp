// The OMPL planners beyond the conformance suite: seeding, approximate results, stop token,
// bad requests and the factory's kind checks.
#include <gtest/gtest.h>

#include <cmath>
#include <stop_token>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/planner/single_robot/ompl_omni_planner.hpp"
#include "fleetnav/planner/single_robot/ompl_reeds_shepp_planner.hpp"
#include "fleetnav/planner/single_robot/planner_factory.hpp"
#include "test_maps.hpp"

namespace fleetnav::planner {
namespace {

Costmap MakeCostmap(const OccupancyGrid& grid, const RobotModel& model) {
  CostmapParams cp;
  cp.padding_m = 0.08;
  return Costmap::Build(grid, model.footprint_m, cp).value();
}

PathRequest DoorRequest() {
  PathRequest req;
  // Both beside the wall at y = 14.5 m: the way round goes through the door.
  req.start = Pose2(3.0, 14.5, 0.0);
  req.goal = Pose2(21.0, 14.5, kPi / 2);
  req.time_limit_s = 5.0;
  return req;
}

bool SamePath(const PathResult& a, const PathResult& b) {
  if (a.poses.size() != b.poses.size()) return false;
  for (size_t i = 0; i < a.poses.size(); ++i) {
    if (!a.poses[i].IsNear(b.poses[i], 0.0, 0.0)) return false;
  }
  return true;
}

TEST(OmplPlannerTest, OneSeedGivesOnePathAndSeedsDiffer) {
  const RobotModel omni = MecanumPlatformModel();
  const RobotModel car = AckermannDeliveryModel();
  Costmap omni_map = MakeCostmap(testing::DoorGrid(), omni);
  Costmap car_map = MakeCostmap(testing::DoorGrid(), car);
  int differing = 0;
  for (uint32_t seed : {1u, 2u, 3u}) {
    OmplPlannerParams params;
    params.seed = seed;
    OmplOmniPlanner a(&omni_map, params), b(&omni_map, params);
    absl::StatusOr<PathResult> ra = a.Plan(DoorRequest());
    absl::StatusOr<PathResult> rb = b.Plan(DoorRequest());
    ASSERT_TRUE(ra.ok() && rb.ok());
    EXPECT_TRUE(SamePath(*ra, *rb)) << "seed " << seed;
    // The same planner planning again starts from the same seed.
    absl::StatusOr<PathResult> again = a.Plan(DoorRequest());
    ASSERT_TRUE(again.ok());
    EXPECT_TRUE(SamePath(*ra, *again)) << "seed " << seed;
    OmplReedsSheppPlanner c(&car_map, 1.0, params), d(&car_map, 1.0, params);
    absl::StatusOr<PathResult> rc = c.Plan(DoorRequest());
    absl::StatusOr<PathResult> rd = d.Plan(DoorRequest());
    ASSERT_TRUE(rc.ok() && rd.ok());
    EXPECT_TRUE(SamePath(*rc, *rd)) << "seed " << seed;
    params.seed = seed + 100;
    OmplOmniPlanner other(&omni_map, params);
    absl::StatusOr<PathResult> ro = other.Plan(DoorRequest());
    ASSERT_TRUE(ro.ok());
    differing += SamePath(*ra, *ro) ? 0 : 1;
  }
  EXPECT_GE(differing, 2);  // the seed is really used
}

TEST(OmplPlannerTest, EnclosedGoalGivesAnApproximatePathOrNotFound) {
  OccupancyGrid grid = testing::DoorGrid();
  for (int x = 150; x < 238; ++x) {
    grid.SetValue({x, 60}, OccupancyGrid::kOccupiedValue);
    grid.SetValue({x, 61}, OccupancyGrid::kOccupiedValue);
  }
  for (int y = 2; y < 62; ++y) {
    grid.SetValue({150, y}, OccupancyGrid::kOccupiedValue);
    grid.SetValue({151, y}, OccupancyGrid::kOccupiedValue);
  }
  const RobotModel model = MecanumPlatformModel();
  Costmap costmap = MakeCostmap(grid, model);
  PathRequest req;
  req.start = Pose2(5.0, 8.0, 0.0);
  req.goal = Pose2(20.0, 3.0, 0.0);
  req.time_limit_s = 0.3;
  OmplPlannerParams params;
  OmplOmniPlanner approx(&costmap, params);
  absl::StatusOr<PathResult> r = approx.Plan(req);
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_FALSE(r->exact);
  ASSERT_FALSE(r->poses.empty());
  EXPECT_TRUE(r->poses.front().IsNear(req.start, 1e-9, 1e-9));
  // The closest start-tree pose lies outside the enclosure, nearer the goal than the start.
  EXPECT_LT((r->poses.back().translation() - req.goal.translation()).norm(),
            (req.start.translation() - req.goal.translation()).norm());
  params.allow_approximate = false;
  OmplOmniPlanner strict(&costmap, params);
  EXPECT_EQ(strict.Plan(req).status().code(), absl::StatusCode::kNotFound);
}

TEST(OmplPlannerTest, StopTokenCancels) {
  const RobotModel model = MecanumPlatformModel();
  Costmap costmap = MakeCostmap(testing::DoorGrid(), model);
  OmplOmniPlanner planner(&costmap, OmplPlannerParams{});
  std::stop_source source;
  source.request_stop();
  EXPECT_EQ(planner.Plan(DoorRequest(), source.get_token()).status().code(),
            absl::StatusCode::kCancelled);
}

TEST(OmplPlannerTest, BadRequestsNameTheField) {
  const RobotModel model = AckermannDeliveryModel();
  Costmap costmap = MakeCostmap(testing::DoorGrid(), model);
  OmplReedsSheppPlanner planner(&costmap, 1.1, OmplPlannerParams{});
  auto expect_invalid = [&](const PathRequest& req, const char* field) {
    absl::Status s = planner.Plan(req).status();
    EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument) << field;
    EXPECT_NE(s.message().find(field), std::string::npos) << s;
  };
  PathRequest req = DoorRequest();
  req.start = Pose2(12.0, 2.0, 0.0);  // inside the wall
  expect_invalid(req, "start");
  req = DoorRequest();
  req.goal = Pose2(12.0, 3.0, 0.0);  // in the wall
  expect_invalid(req, "goal");
  req.goal = Pose2(40.0, 3.0, 0.0);  // outside the map
  expect_invalid(req, "goal");
  req = DoorRequest();
  req.goal_tolerance_m = 0.0;
  expect_invalid(req, "goal_tolerance_m");
  req = DoorRequest();
  req.time_limit_s = -1.0;
  expect_invalid(req, "time_limit_s");
  OmplPlannerParams bad;
  bad.seed = 0;
  OmplOmniPlanner unseeded(&costmap, bad);
  absl::Status s = unseeded.Plan(DoorRequest()).status();
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("seed"), std::string::npos) << s;
}

TEST(PlannerFactoryTest, KindMustFitTheKinematics) {
  Costmap costmap = MakeCostmap(testing::DoorGrid(), LelyVectorModel());
  SingleRobotPlannerParams params;
  EXPECT_TRUE(MakeSingleRobotPlanner(&costmap, LelyVectorModel(), params).ok());  // lattice
  params.kind = PlannerKind::kOmplOmni;
  EXPECT_EQ(MakeSingleRobotPlanner(&costmap, LelyVectorModel(), params).status().code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_TRUE(MakeSingleRobotPlanner(&costmap, MecanumPlatformModel(), params).ok());
  params.kind = PlannerKind::kOmplReedsShepp;
  EXPECT_EQ(MakeSingleRobotPlanner(&costmap, MecanumPlatformModel(), params).status().code(),
            absl::StatusCode::kInvalidArgument);
  RobotModel forward_only = AckermannDeliveryModel();
  forward_only.limits.max_reverse_speed_mps = 0.0;
  absl::Status s = MakeSingleRobotPlanner(&costmap, forward_only, params).status();
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("max_reverse_speed_mps"), std::string::npos) << s;
  absl::StatusOr<std::unique_ptr<SingleRobotPlanner>> rs =
      MakeSingleRobotPlanner(&costmap, AckermannDeliveryModel(), params);
  ASSERT_TRUE(rs.ok());
  const RobotModel car = AckermannDeliveryModel();
  EXPECT_NEAR(static_cast<OmplReedsSheppPlanner*>(rs->get())->turning_radius_m(),
              car.wheelbase_m / std::tan(car.limits.max_steering_rad), 1e-12);
  params.ompl.seed = 0;
  EXPECT_EQ(MakeSingleRobotPlanner(&costmap, AckermannDeliveryModel(), params).status().code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(PlannerKindByName("ompl-omni").value(), PlannerKind::kOmplOmni);
  EXPECT_EQ(PlannerKindByName("dubins").status().code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fleetnav::planner
