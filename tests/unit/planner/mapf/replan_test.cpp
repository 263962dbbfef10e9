#include <gtest/gtest.h>

#include "fleetnav/planner/coordination/action_dependency_graph.hpp"
#include "fleetnav/planner/mapf/lns.hpp"
#include "fleetnav/planner/mapf/mapf_planner.hpp"
#include "test_maps.hpp"

namespace fleetnav::planner {
namespace {

using testing::InlineMap;

int At(const std::vector<int>& path, int step) {
  return step < static_cast<int>(path.size()) ? path[step] : path.back();
}

class ReplanSeedTest : public ::testing::TestWithParam<uint64_t> {};

// Forty robots follow a plan; at step 5 robot 0 is blocked where it stands for 8 steps. The
// others have committed to their next two moves, except those whose next moves would run into
// the blocked robot, which have committed to nothing beyond their position. The replan keeps
// every prefix, lets robot 0 wait, and brings everyone home without a conflict or a rotation.
TEST_P(ReplanSeedTest, ALateRobotGetsANewPlanThatKeepsEveryCommittedPrefix) {
  const GridGraph g(testing::Random32Map20());
  const MapfInstance original = RandomInstance(g, 40, GetParam()).value();
  MapfPlannerParams params;
  params.seed = GetParam();
  params.forbid_rotations = true;
  const MapfResult plan = MapfPlanner(params).Solve(original, MapfStopCondition{0.3}).value();
  const int now = 5;
  MapfInstance current = original;
  std::vector<std::vector<int>> committed(original.num_agents());
  const int blocked_at = At(plan.solution.paths[0], now);
  committed[0].assign(9, blocked_at);
  for (int i = 1; i < original.num_agents(); ++i) {
    const std::vector<int>& p = plan.solution.paths[i];
    committed[i] = {At(p, now), At(p, now + 1), At(p, now + 2)};
    const bool runs_into_blocked =
        std::find(committed[i].begin(), committed[i].end(), blocked_at) != committed[i].end();
    if (runs_into_blocked) committed[i].resize(1);
  }
  for (int i = 0; i < original.num_agents(); ++i) current.starts[i] = committed[i][0];

  absl::StatusOr<MapfResult> replanned =
      MapfPlanner(params).Replan(current, committed, MapfStopCondition{0.3});
  ASSERT_TRUE(replanned.ok()) << replanned.status();
  ASSERT_TRUE(ValidateSolution(current, replanned->solution).ok())
      << ValidateSolution(current, replanned->solution);
  for (int i = 0; i < current.num_agents(); ++i) {
    for (size_t k = 0; k < committed[i].size(); ++k) {
      ASSERT_EQ(replanned->solution.paths[i][k], committed[i][k]) << "robot " << i << " step " << k;
    }
  }
  int step = 0;
  EXPECT_TRUE(FindRotation(replanned->solution, &step).empty());
  EXPECT_TRUE(ActionDependencyGraph::Compile(current, replanned->solution).ok());
}

INSTANTIATE_TEST_SUITE_P(Seeds, ReplanSeedTest, ::testing::Values(31, 32, 33, 34, 35));

TEST(ReplanTest, ABlockedRobotInACorridorIsPassedThroughTheBay) {
  // Robot 0 is stuck for four steps at the corridor's left end and must then go right; robot
  // 1 comes from the right and wants the left end. Robot 1 has to use the bay.
  const GridGraph g(InlineMap("@@.@@\n.....\n", 5, 2));
  MapfInstance inst{&g, {g.VertexAt(1, 1), g.VertexAt(4, 1)}, {g.VertexAt(4, 1), g.VertexAt(0, 1)}};
  const std::vector<std::vector<int>> committed = {std::vector<int>(5, g.VertexAt(1, 1)),
                                                   {g.VertexAt(4, 1)}};
  MapfPlannerParams params;
  absl::StatusOr<MapfResult> r =
      MapfPlanner(params).Replan(inst, committed, MapfStopCondition{0.2});
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_TRUE(ValidateSolution(inst, r->solution).ok())
      << ValidateSolution(inst, r->solution) << "\n"
      << FormatPaths(g, r->solution);
  for (int k = 0; k < 5; ++k) EXPECT_EQ(r->solution.paths[0][k], g.VertexAt(1, 1));
  EXPECT_EQ(r->solution.paths[1].back(), g.VertexAt(0, 1));
}

TEST(ReplanTest, WhenNoPriorityOrderWorksTheWholeFleetIsPlannedFromThePrefixEnds) {
  // Robot 0 parks under the bay, robot 1 must pass it to the corridor's left end. Planned first,
  // robot 0 blocks robot 1 for ever; planned second, it is caught in the corridor by robot 1
  // (and held as an obstacle at its start, robot 1 cannot reach its goal). A joint plan exists:
  // robot 0 waits in the bay.
  const GridGraph g(InlineMap("@@.@@\n.....\n", 5, 2));
  MapfInstance inst{&g, {g.VertexAt(0, 1), g.VertexAt(4, 1)}, {g.VertexAt(2, 1), g.VertexAt(0, 1)}};
  MapfPlannerParams params;
  absl::StatusOr<MapfResult> r = MapfPlanner(params).Replan(
      inst, {{g.VertexAt(0, 1)}, {g.VertexAt(4, 1)}}, MapfStopCondition{0.5});
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_TRUE(ValidateSolution(inst, r->solution).ok()) << ValidateSolution(inst, r->solution);
  EXPECT_TRUE(r->solver.starts_with("prioritized-failed+")) << r->solver;
}

TEST(ReplanTest, RejectsPrefixesThatDoNotFit) {
  const GridGraph g(InlineMap(".....\n", 5, 1));
  MapfInstance inst{&g, {0, 4}, {4, 0}};
  MapfPlanner planner(MapfPlannerParams{});
  auto code = [&](const std::vector<std::vector<int>>& committed) {
    return planner.Replan(inst, committed, MapfStopCondition{0.5}).status().code();
  };
  EXPECT_EQ(code({{0}}), absl::StatusCode::kInvalidArgument);          // one prefix missing
  EXPECT_EQ(code({{1}, {4}}), absl::StatusCode::kInvalidArgument);     // not at the start
  EXPECT_EQ(code({{0, 2}, {4}}), absl::StatusCode::kInvalidArgument);  // a jump
  EXPECT_EQ(code({{0, 1, 2}, {4, 3, 2}}), absl::StatusCode::kInvalidArgument);  // they meet
  absl::Status swap =
      planner.Replan(MapfInstance{&g, {1, 2}, {4, 0}}, {{1, 2}, {2, 1}}, MapfStopCondition{0.5})
          .status();
  EXPECT_EQ(swap.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(swap.message().find("swap"), std::string::npos) << swap;
}

TEST(ReplanTest, ImpossibleCommitmentsRunOutOfTime) {
  // Both robots must pass each other in a corridor without a bay.
  const GridGraph g(InlineMap(".....\n", 5, 1));
  MapfInstance inst{&g, {0, 4}, {4, 0}};
  MapfPlannerParams params;
  EXPECT_EQ(MapfPlanner(params).Replan(inst, {{0}, {4}}, MapfStopCondition{0.05}).status().code(),
            absl::StatusCode::kDeadlineExceeded);
}

}  // namespace
}  // namespace fleetnav::planner
