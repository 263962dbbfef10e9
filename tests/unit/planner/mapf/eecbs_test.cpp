#include "fleetnav/planner/mapf/eecbs.hpp"

#include <gtest/gtest.h>

#include "fleetnav/planner/mapf/mapf_planner.hpp"
#include "test_maps.hpp"

namespace fleetnav::planner {
namespace {

using testing::InlineMap;

absl::StatusOr<MapfResult> RunEecbs(const MapfInstance& inst, double w, double time_s = 5.0) {
  EecbsParams p;
  p.suboptimality = w;
  return EecbsSolver(p).Solve(inst, MapfStopCondition{time_s});
}

TEST(EecbsTest, FindsTheOptimalSwapThroughABay) {
  const GridGraph g(InlineMap("@@.@@\n.....\n", 5, 2));
  MapfInstance inst{&g, {g.VertexAt(0, 1), g.VertexAt(4, 1)}, {g.VertexAt(4, 1), g.VertexAt(0, 1)}};
  absl::StatusOr<MapfResult> r = RunEecbs(inst, 1.0);
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_TRUE(ValidateSolution(inst, r->solution).ok());
  EXPECT_EQ(SumOfCosts(inst, r->solution), 11);
}

TEST(EecbsTest, OptimalOnACrossingWithKnownCost) {
  // Two agents cross at the centre of a plus; one must wait one step.
  const GridGraph g(InlineMap("@.@\n...\n@.@\n", 3, 3));
  MapfInstance inst{&g, {g.VertexAt(0, 1), g.VertexAt(1, 0)}, {g.VertexAt(2, 1), g.VertexAt(1, 2)}};
  absl::StatusOr<MapfResult> r = RunEecbs(inst, 1.0);
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_TRUE(ValidateSolution(inst, r->solution).ok());
  EXPECT_EQ(SumOfCosts(inst, r->solution), 5);  // 2 + 3: one waits once
}

TEST(EecbsTest, AgentLeavesItsGoalWhenAnotherMustPass) {
  // Agent 0 starts on its goal in the corridor; agent 1 must pass through it to the end.
  const GridGraph g(InlineMap("@.@@\n....\n", 4, 2));
  MapfInstance inst{&g, {g.VertexAt(1, 1), g.VertexAt(0, 1)}, {g.VertexAt(1, 1), g.VertexAt(3, 1)}};
  absl::StatusOr<MapfResult> r = RunEecbs(inst, 1.0);
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_TRUE(ValidateSolution(inst, r->solution).ok());
  // Agent 0 steps into the bay and back (2), agent 1 goes straight (3).
  EXPECT_EQ(SumOfCosts(inst, r->solution), 5);
}

TEST(EecbsTest, RejectsBadParams) {
  const GridGraph g(InlineMap("...\n", 3, 1));
  MapfInstance inst{&g, {0}, {2}};
  EXPECT_EQ(RunEecbs(inst, 0.5).status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(RunEecbs(inst, 1.1, 0.0).status().code(), absl::StatusCode::kInvalidArgument);
}

class EecbsBoundTest : public ::testing::TestWithParam<uint64_t> {};

TEST_P(EecbsBoundTest, StaysWithinTheBoundOnRandom32With30Agents) {
  absl::StatusOr<MovingAiMap> map = testing::Random32Map20();
  ASSERT_TRUE(map.ok()) << map.status();
  const GridGraph g(*map);
  absl::StatusOr<MapfInstance> inst = RandomInstance(g, 30, GetParam());
  ASSERT_TRUE(inst.ok());
  absl::StatusOr<MapfResult> r = RunEecbs(*inst, 1.1);
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_TRUE(ValidateSolution(*inst, r->solution).ok());
  // soc ≤ w · (lowest open cost) and the search never returns below the lower bound.
  const int64_t lb = SumOfCostsLowerBound(*inst);
  const int64_t soc = SumOfCosts(*inst, r->solution);
  EXPECT_GE(soc, lb);
  EXPECT_LE(static_cast<double>(soc), 1.1 * 1.1 * static_cast<double>(lb));
}

INSTANTIATE_TEST_SUITE_P(Seeds, EecbsBoundTest, ::testing::Values(11, 12, 13, 14, 15));

TEST(MapfPlannerTest, AutoUsesEecbsForFewAgentsAndLacamForMany) {
  absl::StatusOr<MovingAiMap> map = testing::Random32Map20();
  ASSERT_TRUE(map.ok()) << map.status();
  const GridGraph g(*map);
  MapfPlannerParams params;
  params.eecbs_max_agents = 20;
  absl::StatusOr<MapfInstance> few = RandomInstance(g, 10, 3);
  absl::StatusOr<MapfResult> a = MapfPlanner(params).Solve(*few, MapfStopCondition{0.5});
  ASSERT_TRUE(a.ok()) << a.status();
  EXPECT_TRUE(a->solver.starts_with("eecbs")) << a->solver;
  absl::StatusOr<MapfInstance> many = RandomInstance(g, 60, 3);
  absl::StatusOr<MapfResult> b = MapfPlanner(params).Solve(*many, MapfStopCondition{0.2});
  ASSERT_TRUE(b.ok()) << b.status();
  EXPECT_TRUE(b->solver.starts_with("lacam")) << b->solver;
  EXPECT_TRUE(ValidateSolution(*many, b->solution).ok());
}

TEST(MapfPlannerTest, RefusesTwoRobotsSentToOneGoalWhenAskedTo) {
  const GridGraph g(InlineMap("....\n", 4, 1));
  MapfInstance inst{&g, {0, 3}, {1, 1}};
  MapfPlannerParams params;
  params.duplicate_goals = MapfPlannerParams::DuplicateGoals::kRefuse;
  EXPECT_EQ(MapfPlanner(params).Solve(inst, MapfStopCondition{}).status().code(),
            absl::StatusCode::kInvalidArgument);
}

TEST(MapfPlannerTest, TwoRobotsSentToOneGoalOneWaitsBesideIt) {
  // In a corridor the robot nearer the goal takes it and the other stops on its own side.
  const GridGraph g(InlineMap(".....\n", 5, 1));
  MapfInstance inst{&g, {0, 4}, {1, 1}};
  absl::StatusOr<MapfResult> r = MapfPlanner(MapfPlannerParams{}).Solve(inst, MapfStopCondition{});
  ASSERT_TRUE(r.ok()) << r.status();
  ASSERT_EQ(r->planned_goals, (std::vector<int>{1, 2}));
  MapfInstance planned = inst;
  planned.goals = r->planned_goals;
  EXPECT_TRUE(ValidateSolution(planned, r->solution).ok());
}

class DuplicateGoalsTest : public ::testing::TestWithParam<uint64_t> {};

TEST_P(DuplicateGoalsTest, EveryRobotArrivesAtItsGoalOrBesideIt) {
  const GridGraph g(testing::Random32Map20());
  MapfInstance inst = RandomInstance(g, 40, GetParam()).value();
  for (int i = 30; i < 40; ++i) inst.goals[i] = inst.goals[i - 30];  // ten goals twice
  MapfPlannerParams params;
  params.seed = GetParam();
  absl::StatusOr<MapfResult> r = MapfPlanner(params).Solve(inst, MapfStopCondition{0.3});
  ASSERT_TRUE(r.ok()) << r.status();
  MapfInstance planned = inst;
  planned.goals = r->planned_goals;
  EXPECT_TRUE(ValidateSolution(planned, r->solution).ok());
  int substituted = 0;
  for (int i = 0; i < 40; ++i) {
    if (planned.goals[i] == inst.goals[i]) continue;
    ++substituted;
    DistanceTable from_goal(g, inst.goals[i]);
    EXPECT_LE(from_goal.Get(planned.goals[i]), 2) << "robot " << i;
  }
  EXPECT_EQ(substituted, 10);
}

INSTANTIATE_TEST_SUITE_P(Seeds, DuplicateGoalsTest, ::testing::Values(1, 2, 3));

}  // namespace
}  // namespace fleetnav::planner
