// One conformance suite for every MapfSolver: the same instances, the same promises. A solver
// joins by adding a row to Solvers().
#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <ostream>
#include <stop_token>
#include <string>
#include <vector>

#include "fleetnav/planner/mapf/eecbs.hpp"
#include "fleetnav/planner/mapf/lacam.hpp"
#include "fleetnav/planner/mapf/lns.hpp"
#include "fleetnav/planner/mapf/mapf_planner.hpp"
#include "fleetnav/planner/mapf/mapf_solver.hpp"
#include "test_maps.hpp"

namespace fleetnav::planner {
namespace {

constexpr double kOneShotLimitS = 60.0;
constexpr double kAnytimeLimitS = 1.0;

struct SolverCase {
  std::string name;
  std::function<std::unique_ptr<MapfSolver>()> make;
  bool rotation_free = false;  ///< promises plans without rotations
  /// The budget of one Solve. One-shot solvers return at their first plan, so theirs is only a
  /// ceiling and is generous (sanitizer builds run them several times slower); anytime solvers
  /// search until it ends, so theirs is short but still leaves LaCAM's first plan room.
  double time_limit_s = kOneShotLimitS;
};

void PrintTo(const SolverCase& solver, std::ostream* os) { *os << solver.name; }

std::vector<SolverCase> Solvers() {
  auto planner = [](MapfPlannerParams::Selection selection, bool forbid_rotations) {
    return [=] {
      MapfPlannerParams params;
      params.selection = selection;
      params.forbid_rotations = forbid_rotations;
      return std::unique_ptr<MapfSolver>(new MapfPlanner(params));
    };
  };
  using Selection = MapfPlannerParams::Selection;
  return {
      {"lacam",
       [] {
         return std::unique_ptr<MapfSolver>(new LacamSolver({false, 1}));
       }},
      {"lacam_star",
       [] {
         return std::unique_ptr<MapfSolver>(new LacamSolver({true, 1}));
       },
       false, kAnytimeLimitS},
      {"eecbs", [] { return std::unique_ptr<MapfSolver>(new EecbsSolver({1.2})); }},
      {"cbs", [] { return std::unique_ptr<MapfSolver>(new EecbsSolver({1.0})); }},
      {"auto", planner(Selection::kAuto, false), false, kAnytimeLimitS},
      {"auto_rotation_free", planner(Selection::kAuto, true), true, kAnytimeLimitS},
      {"planner_eecbs", planner(Selection::kEecbs, false), false, kAnytimeLimitS},
  };
}

/// The maps the instances live on: a corridor with a bay, and generated maps of the benchmark
/// families (random 20 %, warehouse shelf rows, rooms with one-cell doors).
struct Maps {
  GridGraph bay{testing::InlineMap("@@.@@\n.....\n", 5, 2)};
  GridGraph random{testing::Random32Map20()};
  GridGraph warehouse{
      fleetnav::testing::ToMovingAiMap(fleetnav::testing::WarehouseMapRows(4, 3, 6, 2))};
  GridGraph rooms{fleetnav::testing::ToMovingAiMap(fleetnav::testing::RoomsMapRows(3, 3, 6, 2))};
};

struct InstanceCase {
  std::string name;
  MapfInstance instance;
};

std::vector<InstanceCase> Instances(const Maps& m) {
  const GridGraph& bay = m.bay;
  return {
      {"swap_through_a_bay",
       {&bay, {bay.VertexAt(0, 1), bay.VertexAt(4, 1)}, {bay.VertexAt(4, 1), bay.VertexAt(0, 1)}}},
      {"random32_12_agents_seed1", RandomInstance(m.random, 12, 1).value()},
      {"random32_12_agents_seed2", RandomInstance(m.random, 12, 2).value()},
      {"warehouse_15_agents", RandomInstance(m.warehouse, 15, 3).value()},
      {"rooms_10_agents", RandomInstance(m.rooms, 10, 4).value()},
  };
}

/// The optimal sum of costs of an instance (CBS: EECBS with w = 1), for the bound check.
int64_t OptimalCost(const MapfInstance& instance) {
  absl::StatusOr<MapfResult> optimal = EecbsSolver({1.0}).Solve(instance, {60.0});
  EXPECT_TRUE(optimal.ok()) << optimal.status();
  return optimal.ok() ? SumOfCosts(instance, optimal->solution) : 0;
}

class MapfSolverConformanceTest : public ::testing::TestWithParam<SolverCase> {
 protected:
  Maps maps_;
};

TEST_P(MapfSolverConformanceTest, ValidPlansWithinItsBoundAndEveryObservedPlanBetter) {
  for (const InstanceCase& c : Instances(maps_)) {
    SCOPED_TRACE(c.name);
    std::vector<int64_t> observed;
    std::unique_ptr<MapfSolver> solver = GetParam().make();
    absl::StatusOr<MapfResult> r =
        solver->Solve(c.instance, {GetParam().time_limit_s}, [&](const MapfResult& plan) {
          EXPECT_TRUE(ValidateSolution(c.instance, plan.solution).ok())
              << ValidateSolution(c.instance, plan.solution);
          if (GetParam().rotation_free) {
            EXPECT_EQ(CountRotations(plan.solution), 0);
          }
          observed.push_back(SumOfCosts(c.instance, plan.solution));
        });
    ASSERT_TRUE(r.ok()) << r.status();
    ASSERT_TRUE(ValidateSolution(c.instance, r->solution).ok())
        << ValidateSolution(c.instance, r->solution) << "\n"
        << FormatPaths(*c.instance.graph, r->solution);
    const int64_t cost = SumOfCosts(c.instance, r->solution);
    EXPECT_GE(cost, SumOfCostsLowerBound(c.instance));
    if (GetParam().rotation_free) {
      EXPECT_EQ(CountRotations(r->solution), 0);
    }
    // The observer saw the first plan and every improvement, ending with the plan returned.
    ASSERT_FALSE(observed.empty());
    for (size_t k = 1; k < observed.size(); ++k) EXPECT_LT(observed[k], observed[k - 1]);
    EXPECT_EQ(observed.back(), cost);
    if (solver->SuboptimalityBound() > 0.0) {
      EXPECT_LE(static_cast<double>(cost),
                solver->SuboptimalityBound() * static_cast<double>(OptimalCost(c.instance)));
    }
  }
}

TEST_P(MapfSolverConformanceTest, AStopFromTheObserverEndsTheSearchWithThatPlan) {
  // An anytime solver that ignored the token would keep improving the plan for 20 s.
  const MapfInstance instance = RandomInstance(maps_.random, 15, 5).value();
  std::stop_source source;
  int plans_after_stop = 0;
  int64_t first_cost = -1;
  absl::StatusOr<MapfResult> r =
      GetParam().make()->Solve(instance, {20.0, source.get_token()}, [&](const MapfResult& plan) {
        if (source.stop_requested()) ++plans_after_stop;
        if (first_cost < 0) first_cost = SumOfCosts(instance, plan.solution);
        source.request_stop();
      });
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_TRUE(ValidateSolution(instance, r->solution).ok());
  EXPECT_EQ(plans_after_stop, 0);
  EXPECT_EQ(SumOfCosts(instance, r->solution), first_cost);
}

TEST_P(MapfSolverConformanceTest, AStoppedTokenBeforeAnyPlanIsCancelled) {
  // Sixty agents need more steps than any solver runs between two looks at the token.
  const MapfInstance instance = RandomInstance(maps_.random, 60, 6).value();
  std::stop_source source;
  source.request_stop();
  EXPECT_EQ(GetParam().make()->Solve(instance, {10.0, source.get_token()}).status().code(),
            absl::StatusCode::kCancelled);
}

TEST_P(MapfSolverConformanceTest, BadInstancesAndStopConditionsAreInvalidArguments) {
  const GridGraph& g = maps_.bay;
  const MapfInstance same_start{&g, {0, 0}, {1, 2}};
  absl::Status s = GetParam().make()->Solve(same_start, {1.0}).status();
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument) << s;
  EXPECT_NE(s.message().find("starts[1]"), std::string::npos) << s;
  const MapfInstance fine{&g, {0}, {1}};
  s = GetParam().make()->Solve(fine, {0.0}).status();
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument) << s;
  EXPECT_NE(s.message().find("time_limit_s"), std::string::npos) << s;
}

TEST_P(MapfSolverConformanceTest, AnImpossibleSwapIsNeverAPlan) {
  // Two robots swapping ends of a corridor without a bay: no plan exists.
  const GridGraph g(testing::InlineMap(".....\n", 5, 1));
  const absl::StatusCode code =
      GetParam().make()->Solve({&g, {0, 4}, {4, 0}}, {0.3}).status().code();
  EXPECT_TRUE(code == absl::StatusCode::kNotFound || code == absl::StatusCode::kDeadlineExceeded ||
              code == absl::StatusCode::kResourceExhausted)
      << absl::StatusCodeToString(code);
}

INSTANTIATE_TEST_SUITE_P(EverySolver, MapfSolverConformanceTest, ::testing::ValuesIn(Solvers()),
                         [](const ::testing::TestParamInfo<SolverCase>& info) {
                           return info.param.name;
                         });

}  // namespace
}  // namespace fleetnav::planner
