// The lattice presets of free navigation: for cars in tight places (CarLatticeParams) the
// body's clearance, a gap passed in its middle along its axis, and the exact goal yaw by the
// analytic expansion; for platforms a heuristic that knows where the body fits; for the Lely
// (DifferentialLatticeParams) coastal costs that keep a way across open floor near a wall.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/planner/grid/body_clearance.hpp"
#include "fleetnav/planner/single_robot/planner_factory.hpp"
#include "fleetnav/planner/single_robot/single_robot_planner.hpp"

namespace fleetnav::planner {
namespace {

constexpr double kResolutionM = 0.05;

/// A grid of `width` x `height` cells of 5 cm whose cells are occupied where `occupied` holds
/// for their centre (metres from the grid's corner).
OccupancyGrid GridWhere(int width, int height,
                        const std::function<bool(const Eigen::Vector2d&)>& occupied) {
  OccupancyGrid grid =
      OccupancyGrid::Filled(width, height, kResolutionM, Pose2(), OccupancyGrid::kFreeValue)
          .value();
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      if (occupied(grid.CellToWorld({x, y}))) grid.SetValue({x, y}, OccupancyGrid::kOccupiedValue);
    }
  }
  return grid;
}

/// A 20 x 12 m yard with a north-south row of 0.6 m boxes at x = 10 m whose one gap, centred at
/// y = `gap_centre_m`, is `gap_m` wide; the rest of the row is closed.
OccupancyGrid RowWithOneGap(double gap_m, double gap_centre_m) {
  return GridWhere(400, 240, [&](const Eigen::Vector2d& c) {
    const bool in_row = std::abs(c.x() - 10.0) <= 0.3;
    const bool in_gap = std::abs(c.y() - gap_centre_m) < 0.5 * gap_m;
    return in_row && !in_gap;
  });
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
  EXPECT_LT(clearance.At(Pose2(9.7, 6.0, kPi / 6.0)), centred - 0.1);
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
    out.yaw_at_row_rad = std::max(out.yaw_at_row_rad, std::abs(std::remainder(p.yaw_rad(), kPi)));
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
  const Pose2 goal(5.0, 2.5, -100.0 * kPi / 180.0);  // between 32 bins of 11.25°
  const PathResult path = Plan(CarLatticeParams(), costmap, Pose2(2.0, 8.0, 0.0), goal);
  EXPECT_TRUE(path.poses.back().IsNear(goal, 1e-6, 1e-6));
  // Without the analytic expansion it ends within the request's tolerance only.
  LatticeParams no_shot = CarLatticeParams();
  no_shot.analytic_every = 0;
  const PathResult binned = Plan(no_shot, costmap, Pose2(2.0, 8.0, 0.0), goal);
  EXPECT_FALSE(binned.poses.back().IsNear(goal, 1e-3, 1e-3));
}

/// Switches between driving forward and reversing along a path (each consecutive pair of poses
/// moves along or against the first one's heading).
int Cusps(const PathResult& path) {
  int cusps = 0;
  int direction = 0;
  for (size_t i = 1; i < path.poses.size(); ++i) {
    const Pose2& a = path.poses[i - 1];
    const Pose2& b = path.poses[i];
    const double along =
        (b.x_m() - a.x_m()) * std::cos(a.yaw_rad()) + (b.y_m() - a.y_m()) * std::sin(a.yaw_rad());
    if (std::abs(along) < 1e-6) continue;
    const int d = along > 0.0 ? 1 : -1;
    if (direction != 0 && d != direction) ++cusps;
    direction = d;
  }
  return cusps;
}

TEST(CarLatticeTest, ACuspCostsSoTheCarTurnsRoundForwardWhereThereIsRoom) {
  // The goal lies 2 m behind the car, facing back, on an open yard west of the row: a loop
  // forward costs a little more path than backing into a turn, and a cusp costs 3 m.
  const RobotModel car = AckermannDeliveryModel();
  const Costmap costmap = CostmapOf(RowWithOneGap(1.2, 6.0), car);
  const Pose2 start(5.0, 6.0, 0.0);
  const Pose2 goal(3.0, 6.0, kPi);
  LatticeParams params = CarLatticeParams();
  params.analytic_every = 0;  // the lattice's own choice, without the Reeds-Shepp shot
  EXPECT_EQ(Cusps(Plan(params, costmap, start, goal)), 0);
  params.direction_switch_cost_m = 0.0;
  EXPECT_GE(Cusps(Plan(params, costmap, start, goal)), 1);
  params.direction_switch_cost_m = -1.0;
  EXPECT_EQ(params.Validate().code(), absl::StatusCode::kInvalidArgument);
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
  const OccupancyGrid grid = GridWhere(400, 240, [](const Eigen::Vector2d& c) {
    return std::abs(c.x() - 10.0) <= 0.3 && c.y() < 10.0 && std::abs(c.y() - 3.0) >= 0.3;
  });
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

TEST(PlatformLatticeTest, ACarriedTrolleyPassesANarrowAisleAlongItFromAnyStartYaw) {
  // A 1.03 m aisle across the hall (a shelf aisle beside another trolley): a platform carrying
  // a 1.0 x 0.7 m trolley, 0.9 m wide padded, fits it along its axis and not 6° off it. It
  // starts at 73.5°, which whole heading bins of 22.5° never bring to 0° or 180°.
  const OccupancyGrid grid = GridWhere(400, 240, [](const Eigen::Vector2d& c) {
    return c.x() > 7.0 && c.x() < 13.0 && std::abs(c.y() - 6.0) > 0.515;
  });
  const RobotModel carrying = MecanumPlatformModel().CarryingLoad(Eigen::Vector2d(1.0, 0.7));
  Costmap costmap = CostmapOf(grid, carrying);
  LatticePlanner planner(&costmap, carrying, PlatformLatticeParams());
  PathRequest request;
  request.start = Pose2(4.0, 6.0, DegToRad(73.5));
  request.goal = Pose2(16.0, 6.0, DegToRad(73.5));
  request.time_limit_s = 60.0;
  const PathResult path = planner.Plan(request).value();
  EXPECT_TRUE(path.exact);
  EXPECT_LT(path.length_m, 13.0);
  EXPECT_LT(path.expanded, 500'000);
  for (const Pose2& p : path.poses) {
    if (p.x_m() > 7.0 && p.x_m() < 13.0) {
      EXPECT_NEAR(std::abs(std::remainder(p.yaw_rad(), kPi)), 0.0, 1e-6) << p.DebugString();
    }
  }
}

/// The share of a path's length along which base_link is farther than `reach_m` from every
/// obstacle (measured every 5 cm).
double ShareBeyondReach(const PathResult& path, const Costmap& costmap, double reach_m) {
  double beyond_m = 0.0, total_m = 0.0;
  for (size_t i = 1; i < path.poses.size(); ++i) {
    const Eigen::Vector2d a = path.poses[i - 1].translation(), b = path.poses[i].translation();
    const double length_m = (b - a).norm();
    const int steps = std::max(1, static_cast<int>(std::ceil(length_m / kResolutionM)));
    for (int k = 0; k < steps; ++k) {
      const Eigen::Vector2d p = a + (b - a) * ((k + 0.5) / steps);
      const int cx = static_cast<int>(p.x() / kResolutionM),
                cy = static_cast<int>(p.y() / kResolutionM);
      if (costmap.DistanceToObstacle_m(cx, cy) > reach_m) beyond_m += length_m / steps;
    }
    total_m += length_m;
  }
  return total_m > 0.0 ? beyond_m / total_m : 0.0;
}

TEST(DifferentialLatticeTest, AWayAcrossAnOpenBarnKeepsAWallWithinTheUltrasonicsReach) {
  // A 30 x 16 m barn with nothing in it but its walls; the Lely crosses it 4.5 m from the south
  // wall, beyond its side ultrasonics' 2.5 m, where its localization would only dead-reckon.
  const OccupancyGrid grid = GridWhere(600, 320, [](const Eigen::Vector2d& c) {
    return c.x() < 0.1 || c.y() < 0.1 || c.x() > 29.9 || c.y() > 15.9;  // walls 2 cells thick
  });
  const RobotModel lely = LelyVectorModel();
  Costmap costmap = CostmapOf(grid, lely);
  PathRequest request;
  request.start = Pose2(3.0, 4.5, 0.0);
  request.goal = Pose2(27.0, 4.5, 0.0);
  request.time_limit_s = 30.0;
  const double reach_m = DifferentialLatticeParams().coast_reach_m;
  EXPECT_NEAR(reach_m, 2.5, 1e-9);

  LatticePlanner coastal(&costmap, lely, DifferentialLatticeParams());
  const PathResult near_wall = coastal.Plan(request).value();
  EXPECT_TRUE(near_wall.exact);
  // Down to the wall's reach and along it: most of the way within reach, for a little more way.
  EXPECT_LT(ShareBeyondReach(near_wall, costmap, reach_m), 0.35);
  EXPECT_LT(near_wall.length_m, 24.0 * 1.15);
  // It ends on the goal's place within 5 cm, not the request's 15 cm: the tracker ends there.
  EXPECT_NEAR(request.goal_tolerance_m, 0.15, 1e-9);
  EXPECT_LE((near_wall.poses.back().translation() - request.goal.translation()).norm(), 0.05);

  // Without coastal costs the same search goes straight over the open floor.
  LatticeParams no_coast = DifferentialLatticeParams();
  no_coast.coastal_weight = 0.0;
  LatticePlanner straight(&costmap, lely, no_coast);
  EXPECT_GT(ShareBeyondReach(straight.Plan(request).value(), costmap, reach_m), 0.9);

  no_coast.coastal_weight = -1.0;
  EXPECT_EQ(no_coast.Validate().code(), absl::StatusCode::kInvalidArgument);
}

TEST(NavigationPlannerParamsTest, EveryKindGetsItsLattice) {
  EXPECT_EQ(NavigationPlannerParams(AckermannDeliveryModel()).kind, PlannerKind::kLattice);
  EXPECT_GT(NavigationPlannerParams(AckermannDeliveryModel()).lattice.clearance_weight, 0.0);
  EXPECT_GT(NavigationPlannerParams(LelyVectorModel()).lattice.clearance_weight, 0.0);
  EXPECT_EQ(NavigationPlannerParams(LelyVectorModel()).lattice.escape_m, 0.0);  // never reverses
  EXPECT_EQ(NavigationPlannerParams(MecanumPlatformModel()).lattice.analytic_every, 0);
  // Coastal costs for the Lely's short-range ultrasonics alone: the others see with a laser.
  EXPECT_GT(NavigationPlannerParams(LelyVectorModel()).lattice.coastal_weight, 0.0);
  EXPECT_EQ(NavigationPlannerParams(MecanumPlatformModel()).lattice.coastal_weight, 0.0);
  EXPECT_EQ(NavigationPlannerParams(AckermannDeliveryModel()).lattice.coastal_weight, 0.0);
}

}  // namespace
}  // namespace fleetnav::planner
