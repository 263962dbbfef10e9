#include "fleetnav/planner/coordination/kinematic_traffic.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_replace.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/planner/coordination/kinematic_dependency_graph.hpp"
#include "fleetnav/planner/coordination/traffic_dependencies.hpp"
#include "fleetnav/planner/grid/coarse_grid.hpp"
#include "fleetnav/planner/kinematic/kinematic_mapf.hpp"

namespace fleetnav::planner {
namespace {

// Conflict-based search handles about this many robots within a PlanPaths budget.
constexpr size_t kMaxKinematicRobots = 12;

// Offsets of the cells that a disc of `radius_m` centred in cell (0, 0) touches.
std::vector<std::array<int, 2>> DiscCells(double radius_m, double cell_m) {
  const int reach = static_cast<int>(std::ceil(radius_m / cell_m));
  std::vector<std::array<int, 2>> cells = {{0, 0}};
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      if (dx == 0 && dy == 0) continue;
      const double nx = std::max(0.0, (std::abs(dx) - 0.5) * cell_m);
      const double ny = std::max(0.0, (std::abs(dy) - 0.5) * cell_m);
      if (std::hypot(nx, ny) < radius_m - 1e-9) cells.push_back({dx, dy});
    }
  }
  return cells;
}

// The grid heading (0 = +x, counter-clockwise in quarter turns) nearest to `yaw_rad`.
int NearestHeading(double yaw_rad) {
  const long h = std::lround(yaw_rad / (kPi / 2));
  return static_cast<int>(((h % 4) + 4) % 4);
}

// Differential-drive robots keep a heading on the grid (they turn in place, and the Lely must not
// reverse). Ackermann robots cannot turn in place, which is the grid's only way to turn, so they
// move like omni robots there; their local planner drives the arcs.
bool HasGridHeading(const RobotModel& m) { return m.kinematics == Kinematics::kDifferential; }

}  // namespace

bool UseKinematicTraffic(const std::vector<RobotModel>& models) {
  if (models.size() > kMaxKinematicRobots) return false;
  return std::any_of(models.begin(), models.end(), HasGridHeading);
}

absl::StatusOr<TrafficPlan> PlanKinematicTraffic(const OccupancyGrid& grid,
                                                 const std::vector<TrafficAgent>& agents,
                                                 const std::vector<RobotModel>& models,
                                                 double time_limit_s) {
  double cell_m = std::numeric_limits<double>::infinity();
  double speed_mps = std::numeric_limits<double>::infinity();
  for (const RobotModel& m : models) {
    cell_m = std::min(cell_m, 2.0 * m.CircumscribedRadius());
    speed_mps = std::min(speed_mps, m.limits.max_speed_mps);
  }
  const CoarseGrid coarse = Coarsen(grid, cell_m);
  KinematicMapfProblem problem{&coarse.map, {}};
  for (size_t i = 0; i < agents.size(); ++i) {
    GridRobot r;
    coarse.CellOf(agents[i].start, &r.start_x, &r.start_y);
    coarse.CellOf(agents[i].goal, &r.goal_x, &r.goal_y);
    r.motion.footprint_cells = DiscCells(models[i].CircumscribedRadius(), coarse.cell_m);
    r.motion.has_heading = HasGridHeading(models[i]);
    r.motion.may_reverse = models[i].limits.max_reverse_speed_mps > 0.0;
    r.start_heading = r.motion.has_heading
                          ? NearestHeading(agents[i].start.yaw_rad() - coarse.origin.yaw_rad())
                          : kPlusX;
    problem.robots.push_back(r);
  }
  if (absl::Status s = problem.Validate(); !s.ok()) {
    return absl::InvalidArgumentError(absl::StrReplaceAll(s.message(), {{"robots[", "agents["}}));
  }
  // Goals whose footprints overlap cannot all be held at once.
  for (size_t i = 0; i < agents.size(); ++i) {
    std::vector<int> mine, theirs;
    const GridRobot& a = problem.robots[i];
    CoveredCells(coarse.map, a.motion, {a.goal_x, a.goal_y, kPlusX}, &mine);
    for (size_t j = 0; j < i; ++j) {
      const GridRobot& b = problem.robots[j];
      CoveredCells(coarse.map, b.motion, {b.goal_x, b.goal_y, kPlusX}, &theirs);
      for (int c : mine) {
        if (std::find(theirs.begin(), theirs.end(), c) != theirs.end()) {
          return absl::InvalidArgumentError(
              absl::StrCat("agents[", i, "].goal: overlaps agents[", j, "].goal"));
        }
      }
    }
  }
  KinematicMapfParams params;
  params.time_limit_s = time_limit_s;
  absl::StatusOr<KinematicMapfPlan> solution = PlanKinematicMapf(problem, params);
  if (!solution.ok()) {
    if (!absl::IsInvalidArgument(solution.status())) return solution.status();
    return absl::InvalidArgumentError(
        absl::StrReplaceAll(solution.status().message(), {{"robots[", "agents["}}));
  }
  absl::StatusOr<KinematicDependencyGraph> graph =
      KinematicDependencyGraph::Compile(problem, *solution);
  if (!graph.ok()) return graph.status();

  TrafficPlan plan;
  plan.cell_size_m = coarse.cell_m;
  plan.solver = "kinematic";
  plan.waits_beside_goal.assign(agents.size(), false);
  const double step_s = coarse.cell_m / speed_mps;
  for (size_t i = 0; i < agents.size(); ++i) {
    const std::vector<GridState>& states = solution->states[i];
    std::vector<PlannedPose> path;
    for (size_t t = 0; t < states.size(); ++t) {
      const Eigen::Vector2d at = coarse.CenterOf(states[t].x, states[t].y);
      const double yaw = problem.robots[i].motion.has_heading
                             ? states[t].heading * (kPi / 2) + coarse.origin.yaw_rad()
                             : agents[i].start.yaw_rad();
      path.push_back({t * step_s, Pose2(at.x(), at.y(), yaw)});
    }
    path.front().pose = agents[i].start;
    path.back().pose = agents[i].goal;
    plan.sum_of_costs_s += (states.size() - 1) * step_s;
    plan.makespan_s = std::max(plan.makespan_s, path.back().t_s);
    plan.paths.push_back(std::move(path));
  }
  AppendDependencies(graph->graph(), agents, &plan);
  return plan;
}

}  // namespace fleetnav::planner
