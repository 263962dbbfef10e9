// The lattice planner for cars in tight places (CarLatticeParams): the body's clearance, a gap
// passed in its middle along its axis, and the exact goal yaw by the analytic expansion.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/planner/grid/body_clearance.hpp"
#include "fleetnav/planner/single_robot/planner_factory.hpp"
#include "fleetnav/planner/single_robot/single_robot_planner.hpp"

namespace fleetnav::planner {
namespace {

constexpr double kResolutionM = 0.05;

/// A 20 x 12 m yard with a north-south row of 0.6 m boxes at x = 10 m whose one gap, centred at
/// y = `gap_centre_m`, is `gap_m` wide; the rest of the row is closed.
OccupancyGrid RowWithOneGap(double gap_m, double gap_centre_m) {
  OccupancyGrid grid =
      OccupancyGrid::Filled(400, 240, kResolutionM, Pose2(), OccupancyGrid::kFreeValue).value();
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      const Eigen::Vector2d c = grid.CellToWorld({x, y});
      const bool in_row = std::abs(c.x() - 10.0) <= 0.3;
      const bool in_gap = std::abs(c.y() - gap_centre_m) < 0.5 * gap_m;
      if (in_row && !in_gap) grid.SetValue({x, y}, OccupancyGrid::kOccupiedValue);
    }
  }
  return grid;
}

Costmap CostmapOf(const OccupancyGrid& grid, const RobotModel& model) {
  CostmapParams params;
  params.padding_m = 0.1;  // as the agent's free navigation plans
  return Costmap::Build(grid, model.footprint_m, params).value();
}

TEST(BodyClearanceTest, NeverOverstatesAndIsCloseBesideTheBody) {
  const RobotModel car = AckermannDeliveryModel();  // 0.9 x 0.6 m, base_link 0.15 m from the back
  const OccupancyGrid grid = RowWithOneGap(1.2, 6.0);
  const Costmap costmap = CostmapOf(grid, car);
  const BodyClearance clearance(&costmap, car.footprint_m);
  // Centred in the gap along its axis: 0.3 m a side, less what the covering discs stick out.
  const double centred = clearance.At(Pose2(9.7, 6.0, 0.0));
  EXPECT_LE(centred, 0.3 + kResolutionM);
  EXPECT_GE(centred, 0.2);
  // 10 cm off the middle: 10 cm less.
  EXPECT_NEAR(clearance.At(Pose2(9.7, 6.1, 0.0)), centred - 0.1, kResolutionM);
  // Across the gap at 30°: its corners come near the boxes.
  EXPECT_LT(clearance.At(Pose2(9.7, 6.0, M_PI / 6.0)), centred - 0.1);
  // Touching: nothing positive.
  EXPECT_LE(clearance.At(Pose2(9.7, 6.35, 0.0)), 0.0);
  // Far from everything.
  EXPECT_GT(clearance.At(Pose2(3.0, 3.0, 1.0)), 2.0);
}

struct GapCrossing {
  double least_clearance_m = std::numeric_limits<double>::infinity();  ///< along the whole path
  double yaw_at_row_rad = 0.0;  ///< from the gap's axis, where the body's middle is in the row
};

/// How a path's body passes the row at x = 10 m: the least clearance of the body (without
/// the planner's padding) along the path, and the largest angle to the row's normal while the
/// middle of the body is within the row (x = 10 ± 0.3 m).
GapCrossing Crossing(const PathResult& path, const BodyClearance& clearance) {
  GapCrossing out;
  for (const Pose2& p : path.poses) {
    out.least_clearance_m = std::min(out.least_clearance_m, clearance.At(p));
    const double middle_x = p.x_m() + 0.3 * std::cos(p.yaw_rad());
    if (std::abs(middle_x - 10.0) > 0.3) continue;
    out.yaw_at_row_rad = std::max(out.yaw_at_row_rad, std::abs(std::remainder(p.yaw_rad(), M_PI)));
  }
  return out;
}

PathResult Plan(const LatticeParams& params, const Costmap& grid_costmap, const Pose2& start,
                const Pose2& goal) {
  Costmap costmap = grid_costmap;
  LatticePlanner planner(&costmap, AckermannDeliveryModel(), params);
  PathRequest request;
  request.start = start;
  request.goal = goal;
  request.goal_tolerance_rad = 0.1;
  request.time_limit_s = 30.0;  // the expansion limit decides, not the machine
  PathResult path = planner.Plan(request).value();
  EXPECT_TRUE(path.exact);
  return path;
}

TEST(CarLatticeTest, PassesAGapWithAFifthOfItsWidthASideInTheMiddleAlongItsAxis) {
  const RobotModel car = AckermannDeliveryModel();
  const Costmap costmap = CostmapOf(RowWithOneGap(1.2, 6.0), car);
  const BodyClearance clearance(&costmap, car.footprint_m);
  // Centred in the gap along its axis: the most clearance there is.
  const double best_m = clearance.At(Pose2(9.7, 6.0, 0.0));
  // The goal lies 3 m north of the gap's line: the shortest way crosses the row at a slant.
  const Pose2 start(4.0, 4.5, 0.0);
  const Pose2 goal(16.0, 9.0, 0.0);
  const GapCrossing car_lattice =
      Crossing(Plan(CarLatticeParams(), costmap, start, goal), clearance);
  EXPECT_GE(car_lattice.least_clearance_m, best_m - 0.06);
  EXPECT_LE(car_lattice.yaw_at_row_rad, 0.2);  // within one heading bin of the axis
  // Length alone takes the gap near its edge and slanted.
  LatticeParams by_length = CarLatticeParams();
  by_length.clearance_weight = 0.0;
  const GapCrossing plain = Crossing(Plan(by_length, costmap, start, goal), clearance);
  EXPECT_LT(plain.least_clearance_m, car_lattice.least_clearance_m - 0.05);
  EXPECT_GT(plain.yaw_at_row_rad, car_lattice.yaw_at_row_rad);
}

TEST(CarLatticeTest, ReachesAGoalYawBetweenHeadingBinsExactly) {
  const RobotModel car = AckermannDeliveryModel();
  const Costmap costmap = CostmapOf(RowWithOneGap(1.2, 6.0), car);
  const Pose2 goal(5.0, 2.5, -100.0 * M_PI / 180.0);  // between 32 bins of 11.25°
  const PathResult path = Plan(CarLatticeParams(), costmap, Pose2(2.0, 8.0, 0.0), goal);
  EXPECT_TRUE(path.poses.back().IsNear(goal, 1e-6, 1e-6));
  // Without the analytic expansion it ends within the request's tolerance only.
  LatticeParams no_shot = CarLatticeParams();
  no_shot.analytic_every = 0;
  const PathResult binned = Plan(no_shot, costmap, Pose2(2.0, 8.0, 0.0), goal);
  EXPECT_FALSE(binned.poses.back().IsNear(goal, 1e-3, 1e-3));
}

TEST(CarLatticeTest, ArcsKeepASteeringMarginAndBadParamsAreRefused) {
  const RobotModel car = AckermannDeliveryModel();
  Costmap costmap = CostmapOf(RowWithOneGap(1.2, 6.0), car);
  const LatticePlanner planner(&costmap, car, CarLatticeParams());
  EXPECT_NEAR(planner.turning_radius_m(), 1.3 * car.wheelbase_m / std::tan(0.5), 1e-9);
  LatticeParams bad = CarLatticeParams();
  bad.turning_radius_factor = 0.9;
  EXPECT_EQ(bad.Validate().code(), absl::StatusCode::kInvalidArgument);
  bad = CarLatticeParams();
  bad.clearance_weight = -1.0;
  EXPECT_EQ(bad.Validate().code(), absl::StatusCode::kInvalidArgument);
  bad = CarLatticeParams();
  bad.preferred_clearance_m = 0.0;
  EXPECT_EQ(bad.Validate().code(), absl::StatusCode::kInvalidArgument);
  bad = CarLatticeParams();
  bad.analytic_every = -1;
  EXPECT_EQ(bad.Validate().code(), absl::StatusCode::kInvalidArgument);
}

TEST(CarLatticeTest, ACarThatHasTouchedABoxBacksOutAndGoesOnButAPoseInsideOneIsRefused) {
  const RobotModel car = AckermannDeliveryModel();
  Costmap costmap = CostmapOf(RowWithOneGap(1.2, 6.0), car);
  const BodyClearance clearance(&costmap, car.footprint_m);
  // Nose against the row, 2 cm off a box's face (x = 9.7): inside the padding, not through.
  const Pose2 touching(9.7 - 0.75 - 0.02, 3.0, 0.0);
  ASSERT_FALSE(costmap.PoseFree(touching.x_m(), touching.y_m(), touching.yaw_rad()));
  PathRequest request;
  request.start = touching;
  request.goal = Pose2(16.0, 9.0, 0.0);
  request.goal_tolerance_rad = 0.1;
  request.time_limit_s = 30.0;
  LatticePlanner planner(&costmap, car, CarLatticeParams());
  const absl::StatusOr<PathResult> path = planner.Plan(request);
  ASSERT_TRUE(path.ok()) << path.status();
  EXPECT_TRUE(path->exact);
  // It reverses first, each pose clearer than the last until free, within escape_m.
  ASSERT_GE(path->poses.size(), 3u);
  EXPECT_LT(path->poses[1].x_m(), touching.x_m());
  double travelled_m = 0.0;
  for (size_t i = 1; i < path->poses.size(); ++i) {
    const Pose2& p = path->poses[i];
    if (costmap.PoseFree(p.x_m(), p.y_m(), p.yaw_rad())) break;
    EXPECT_GT(clearance.At(p), clearance.At(path->poses[i - 1]));
    travelled_m += (p.translation() - path->poses[i - 1].translation()).norm();
  }
  EXPECT_LE(travelled_m, CarLatticeParams().escape_m + 0.5);
  // Without escaping, the same start is refused; and a pose 0.3 m into the row always is.
  LatticeParams no_escape = CarLatticeParams();
  no_escape.escape_m = 0.0;
  LatticePlanner refusing(&costmap, car, no_escape);
  EXPECT_EQ(refusing.Plan(request).status().code(), absl::StatusCode::kInvalidArgument);
  request.start = Pose2(9.7 - 0.75 + 0.3, 3.0, 0.0);
  EXPECT_EQ(planner.Plan(request).status().code(), absl::StatusCode::kInvalidArgument);
}

TEST(PlatformLatticeTest, AGapTheInscribedCircleFitsAndTheBodyDoesNotDoesNotDrawTheSearchIn) {
  // A store: a shelf row across the hall at x = 10 m with a 0.6 m gap at y = 3 m (the space
  // between a trolley's legs): the platform's padded inscribed circle passes it, its 0.68 m
  // padded width does not at any yaw. The way round the row's north end is twice as long.
  OccupancyGrid grid =
      OccupancyGrid::Filled(400, 240, kResolutionM, Pose2(), OccupancyGrid::kFreeValue).value();
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      const Eigen::Vector2d c = grid.CellToWorld({x, y});
      if (std::abs(c.x() - 10.0) <= 0.3 && c.y() < 10.0 && std::abs(c.y() - 3.0) >= 0.3) {
        grid.SetValue({x, y}, OccupancyGrid::kOccupiedValue);
      }
    }
  }
  const RobotModel platform = MecanumPlatformModel();
  Costmap costmap = CostmapOf(grid, platform);
  LatticePlanner planner(&costmap, platform, PlatformLatticeParams());
  PathRequest request;
  request.start = Pose2(6.0, 3.0, 0.0);
  request.goal = Pose2(14.0, 3.0, 0.0);
  request.time_limit_s = 30.0;
  const PathResult path = planner.Plan(request).value();
  EXPECT_TRUE(path.exact);
  EXPECT_GT(path.length_m, 16.0);  // round the row's end, not 8 m straight through
  // A heuristic over the cells the body fits in at some yaw knows the gap is closed: the
  // search goes round at once (a heuristic through the gap spent its whole budget of 3 M).
  EXPECT_LT(path.expanded, 100'000);
}

TEST(NavigationPlannerParamsTest, EveryKindGetsItsLattice) {
  EXPECT_EQ(NavigationPlannerParams(AckermannDeliveryModel()).kind, PlannerKind::kLattice);
  EXPECT_GT(NavigationPlannerParams(AckermannDeliveryModel()).lattice.clearance_weight, 0.0);
  EXPECT_GT(NavigationPlannerParams(LelyVectorModel()).lattice.clearance_weight, 0.0);
  EXPECT_EQ(NavigationPlannerParams(LelyVectorModel()).lattice.escape_m, 0.0);  // never reverses
  EXPECT_EQ(NavigationPlannerParams(MecanumPlatformModel()).lattice.analytic_every, 0);
}

}  // namespace
}  // namespace fleetnav::planner
