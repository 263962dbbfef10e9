#include "fleetnav/planner/mapf/lacam.hpp"

#include <gtest/gtest.h>

#include "fleetnav/planner/mapf/mapf_planner.hpp"
#include "test_maps.hpp"

namespace fleetnav::planner {
namespace {

using testing::InlineMap;

absl::StatusOr<MapfResult> RunLacam(const MapfInstance& inst, double time_s, uint64_t seed,
                                    bool anytime = true) {
  LacamParams p;
  p.seed = seed;
  p.anytime = anytime;
  LacamSolver solver(p);
  return solver.Solve(inst, MapfStopCondition{time_s});
}

TEST(LacamTest, SolvesTrivialAndAlreadySolvedInstances) {
  const GridGraph g(InlineMap("...\n", 3, 1));
  MapfInstance at_goal{&g, {0, 2}, {0, 2}};
  absl::StatusOr<MapfResult> r = RunLacam(at_goal, 1.0, 1);
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(SumOfCosts(at_goal, r->solution), 0);
  EXPECT_TRUE(ValidateSolution(at_goal, r->solution).ok());
}

TEST(LacamTest, SwapsInACorridorWithOneSideBay) {
  // Two agents swap ends of a corridor; the only passing place is the bay above x = 2.
  const GridGraph g(InlineMap("@@.@@\n.....\n", 5, 2));
  MapfInstance inst{&g, {g.VertexAt(0, 1), g.VertexAt(4, 1)}, {g.VertexAt(4, 1), g.VertexAt(0, 1)}};
  for (uint64_t seed = 0; seed < 5; ++seed) {
    absl::StatusOr<MapfResult> r = RunLacam(inst, 2.0, seed);
    ASSERT_TRUE(r.ok()) << r.status();
    EXPECT_TRUE(ValidateSolution(inst, r->solution).ok());
    // Optimal sum of costs: one agent steps into the bay at t = 3 and out at t = 4 while the
    // other passes below it: 5 + 6 = 11 (lower bound 8).
    EXPECT_EQ(SumOfCosts(inst, r->solution), 11) << "seed " << seed;
    EXPECT_TRUE(r->proven_optimal);
  }
}

TEST(LacamTest, ReportsUnsolvableSwapOnABareLine) {
  const GridGraph g(InlineMap("...\n", 3, 1));
  MapfInstance inst{&g, {0, 2}, {2, 0}};
  absl::StatusOr<MapfResult> r = RunLacam(inst, 2.0, 0);
  EXPECT_EQ(r.status().code(), absl::StatusCode::kNotFound);
}

TEST(LacamTest, RejectsBadParamsAndInstances) {
  const GridGraph g(InlineMap("...\n", 3, 1));
  MapfInstance inst{&g, {0, 1}, {2, 2}};
  EXPECT_EQ(RunLacam(inst, 1.0, 0).status().code(), absl::StatusCode::kInvalidArgument);
  MapfInstance ok{&g, {0}, {2}};
  EXPECT_EQ(RunLacam(ok, -1.0, 0).status().code(), absl::StatusCode::kInvalidArgument);
}

TEST(LacamTest, StopTokenCancelsBeforeAPlan) {
  const GridGraph g(InlineMap(".....\n.....\n", 5, 2));
  MapfInstance inst{&g, {0, 1}, {9, 8}};
  std::stop_source source;
  source.request_stop();
  LacamSolver solver(LacamParams{});
  absl::StatusOr<MapfResult> r = solver.Solve(inst, MapfStopCondition{10.0, source.get_token()});
  // Either cancelled at once, or found trivially before the first check; never a bad plan.
  if (r.ok()) {
    EXPECT_TRUE(ValidateSolution(inst, r->solution).ok());
  } else {
    EXPECT_EQ(r.status().code(), absl::StatusCode::kCancelled);
  }
}

class LacamBenchmarkMapTest : public ::testing::TestWithParam<uint64_t> {};

TEST_P(LacamBenchmarkMapTest, SolvesRandom32With100AgentsValidly) {
  absl::StatusOr<MovingAiMap> map = testing::Random32Map20();
  ASSERT_TRUE(map.ok()) << map.status();
  const GridGraph g(*map);
  absl::StatusOr<MapfInstance> inst = RandomInstance(g, 100, GetParam());
  ASSERT_TRUE(inst.ok()) << inst.status();
  absl::StatusOr<MapfResult> first = RunLacam(*inst, 5.0, GetParam(), /*anytime=*/false);
  ASSERT_TRUE(first.ok()) << first.status();
  EXPECT_TRUE(ValidateSolution(*inst, first->solution).ok());
  const int64_t lb = SumOfCostsLowerBound(*inst);
  const int64_t first_soc = SumOfCosts(*inst, first->solution);
  EXPECT_GE(first_soc, lb);
  // Refinement never makes the plan worse than the first one found with the same seed.
  absl::StatusOr<MapfResult> refined = RunLacam(*inst, 0.3, GetParam(), /*anytime=*/true);
  ASSERT_TRUE(refined.ok()) << refined.status();
  EXPECT_TRUE(ValidateSolution(*inst, refined->solution).ok());
  EXPECT_LE(SumOfCosts(*inst, refined->solution), first_soc);
  EXPECT_GE(SumOfCosts(*inst, refined->solution), lb);
}

INSTANTIATE_TEST_SUITE_P(Seeds, LacamBenchmarkMapTest, ::testing::Values(1, 2, 3, 4, 5));

TEST(LacamTest, SolvesTheFirst50ScenarioAgentsAboveTheLowerBound) {
  absl::StatusOr<MovingAiMap> map = testing::Random32Map20();
  ASSERT_TRUE(map.ok()) << map.status();
  absl::StatusOr<std::vector<ScenarioEntry>> scen =
      ParseMovingAiScenario(fleetnav::testing::ScenarioText(
          fleetnav::testing::RandomMapRows(32, 32, 20, 1), "random-32-32-20.map", 100, 1));
  ASSERT_TRUE(scen.ok()) << scen.status();
  const GridGraph g(*map);
  absl::StatusOr<MapfInstance> inst = InstanceFromScenario(g, *scen, 50);
  ASSERT_TRUE(inst.ok()) << inst.status();
  MapfPlannerParams params;
  absl::StatusOr<MapfResult> r = MapfPlanner(params).Solve(*inst, MapfStopCondition{0.3});
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_TRUE(ValidateSolution(*inst, r->solution).ok());
  EXPECT_GE(SumOfCosts(*inst, r->solution), SumOfCostsLowerBound(*inst));
}

}  // namespace
}  // namespace fleetnav::planner
