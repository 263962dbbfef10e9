#include "fleetnav/planner/mapf/mapf.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "test_maps.hpp"

namespace fleetnav::planner {
namespace {

using ::testing::HasSubstr;
using testing::InlineMap;

// A 4 x 3 open grid.
GridGraph OpenGraph() { return GridGraph(InlineMap("....\n....\n....\n", 4, 3)); }

TEST(GridGraphTest, NumbersFreeCellsAndLinksFourNeighbours) {
  const GridGraph g(InlineMap(".@.\n...\n", 3, 2));
  EXPECT_EQ(g.size(), 5);
  EXPECT_EQ(g.VertexAt(1, 0), GridGraph::kNone);
  const int corner = g.VertexAt(0, 0);
  EXPECT_EQ(g.Degree(corner), 1);
  EXPECT_TRUE(g.Adjacent(corner, g.VertexAt(0, 1)));
  EXPECT_FALSE(g.Adjacent(corner, g.VertexAt(2, 0)));
  EXPECT_EQ(g.Degree(g.VertexAt(1, 1)), 2);
  EXPECT_EQ(g.X(g.VertexAt(2, 1)), 2);
  EXPECT_EQ(g.Y(g.VertexAt(2, 1)), 1);
}

TEST(DistanceTableTest, MatchesManhattanOnOpenGridAndDetoursAroundWalls) {
  const GridGraph open = OpenGraph();
  DistanceTable t(open, open.VertexAt(0, 0));
  EXPECT_EQ(t.Get(open.VertexAt(3, 2)), 5);
  EXPECT_EQ(t.Get(open.VertexAt(0, 0)), 0);
  const GridGraph wall(InlineMap("...\n@@.\n...\n", 3, 3));
  DistanceTable w(wall, wall.VertexAt(0, 2));
  EXPECT_EQ(w.Get(wall.VertexAt(0, 0)), 6);
  const GridGraph split(InlineMap(".@.\n", 3, 1));
  DistanceTable s(split, split.VertexAt(0, 0));
  EXPECT_EQ(s.Get(split.VertexAt(2, 0)), DistanceTable::kUnreachable);
}

TEST(MapfInstanceTest, RejectsDuplicateGoalsNamingBothAgents) {
  const GridGraph g = OpenGraph();
  MapfInstance inst{&g, {g.VertexAt(0, 0), g.VertexAt(1, 0)}, {g.VertexAt(3, 2), g.VertexAt(3, 2)}};
  const absl::Status s = inst.Validate();
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(s.message()), HasSubstr("goals[1]: same vertex as goals[0]"));
}

TEST(MapfInstanceTest, RejectsDuplicateStartsAndUnreachableGoals) {
  const GridGraph g(InlineMap("..@.\n", 4, 1));
  MapfInstance dup{&g, {0, 0}, {1, 2}};
  EXPECT_EQ(dup.Validate().code(), absl::StatusCode::kInvalidArgument);
  MapfInstance cut{&g, {0}, {g.VertexAt(3, 0)}};
  EXPECT_THAT(std::string(cut.Validate().message()), HasSubstr("unreachable"));
}

TEST(MapfMetricsTest, CostCountsUntilLastArrival) {
  EXPECT_EQ(PathCost({5, 5, 5}, 5), 0);
  EXPECT_EQ(PathCost({1, 2, 3}, 3), 2);
  EXPECT_EQ(PathCost({3, 2, 3, 3}, 3), 2);  // leaves its goal and comes back
}

TEST(ValidatorTest, AcceptsAValidPlanAndComputesMetrics) {
  const GridGraph g = OpenGraph();
  const int a = g.VertexAt(0, 0), b = g.VertexAt(1, 0), c = g.VertexAt(2, 0);
  MapfInstance inst{&g, {a, c}, {b, g.VertexAt(2, 1)}};
  MapfSolution sol{{{a, b}, {c, g.VertexAt(2, 1)}}};
  EXPECT_TRUE(ValidateSolution(inst, sol).ok());
  EXPECT_EQ(SumOfCosts(inst, sol), 2);
  EXPECT_EQ(Makespan(inst, sol), 1);
  EXPECT_EQ(SumOfCostsLowerBound(inst), 2);
  EXPECT_EQ(FormatPaths(g, sol), "0: 0,0 1,0\n1: 2,0 2,1\n");
}

TEST(ValidatorTest, FindsVertexEdgeJumpAndEndpointErrors) {
  const GridGraph g = OpenGraph();
  const int a = g.VertexAt(0, 0), b = g.VertexAt(1, 0), c = g.VertexAt(2, 0);
  MapfInstance swap{&g, {a, b}, {b, a}};
  EXPECT_THAT(std::string(ValidateSolution(swap, {{{a, b}, {b, a}}}).message()),
              HasSubstr("edge conflict"));
  MapfInstance meet{&g, {a, c}, {b, g.VertexAt(1, 1)}};
  EXPECT_THAT(std::string(ValidateSolution(meet, {{{a, b}, {c, b, g.VertexAt(1, 1)}}}).message()),
              HasSubstr("vertex conflict"));
  MapfInstance jump{&g, {a}, {c}};
  EXPECT_THAT(std::string(ValidateSolution(jump, {{{a, c}}}).message()), HasSubstr("jump"));
  EXPECT_THAT(std::string(ValidateSolution(jump, {{{a, b}}}).message()), HasSubstr("goal"));
  EXPECT_THAT(std::string(ValidateSolution(jump, {{{b, c}}}).message()), HasSubstr("start"));
  // An agent that finished earlier still occupies its goal.
  MapfInstance rest{&g, {a, c}, {b, g.VertexAt(0, 1)}};
  EXPECT_THAT(
      std::string(ValidateSolution(rest, {{{a, b}, {c, b, a, g.VertexAt(0, 1)}}}).message()),
      HasSubstr("vertex conflict"));
}

TEST(RandomInstanceTest, IsSeededDistinctAndInOneComponent) {
  const GridGraph g(InlineMap("....@..\n....@..\n", 7, 2));
  absl::StatusOr<MapfInstance> a = RandomInstance(g, 5, 7);
  absl::StatusOr<MapfInstance> b = RandomInstance(g, 5, 7);
  ASSERT_TRUE(a.ok()) << a.status();
  EXPECT_EQ(a->starts, b->starts);
  EXPECT_EQ(a->goals, b->goals);
  EXPECT_TRUE(a->Validate().ok());
  for (int v : a->starts) EXPECT_LT(g.X(v), 4);
  EXPECT_EQ(RandomInstance(g, 9, 7).status().code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fleetnav::planner
