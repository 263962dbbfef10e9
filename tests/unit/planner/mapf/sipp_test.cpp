#include "fleetnav/planner/mapf/sipp.hpp"

#include <gtest/gtest.h>

#include "fleetnav/planner/mapf/constraint_table.hpp"
#include "test_maps.hpp"

namespace fleetnav::planner {
namespace {

using testing::InlineMap;

TEST(ConstraintTableTest, HardStepsSplitTheSafeIntervals) {
  ConstraintTable table(4);
  table.AddHardVertex(2, 3);
  table.AddHardVertex(2, 5);
  const std::vector<SafeInterval>& iv = table.Intervals(2);
  ASSERT_EQ(iv.size(), 3u);
  EXPECT_EQ(iv[0].begin_step, 0);
  EXPECT_EQ(iv[0].end_step, 3);
  EXPECT_EQ(iv[1].begin_step, 4);
  EXPECT_EQ(iv[1].end_step, 5);
  EXPECT_EQ(iv[2].begin_step, 6);
  EXPECT_EQ(iv[2].end_step, ConstraintTable::kForever);
  // An untouched vertex is free for ever.
  ASSERT_EQ(table.Intervals(0).size(), 1u);
  EXPECT_EQ(table.Intervals(0)[0].end_step, ConstraintTable::kForever);
}

TEST(ConstraintTableTest, AParkedHardPathEndsTheLastInterval) {
  ConstraintTable table(3);
  table.AddHardPath({0, 1, 2}, /*start_step=*/0);
  ASSERT_EQ(table.Intervals(2).size(), 1u);
  EXPECT_EQ(table.Intervals(2)[0].end_step, 2);
  EXPECT_TRUE(table.HardEdgeBlocked(1, 0, 1));  // the swap of the first move
  EXPECT_FALSE(table.HardEdgeBlocked(0, 1, 1));
  table.RemoveHardPath({0, 1, 2}, 0);
  EXPECT_EQ(table.Intervals(2)[0].end_step, ConstraintTable::kForever);
  EXPECT_FALSE(table.HardEdgeBlocked(1, 0, 1));
}

TEST(ConstraintTableTest, SoftStepsBecomeOneStepConflictIntervals) {
  ConstraintTable table(3);
  table.AddSoftPath({0, 1, 2}, 0);
  table.AddSoftPath({2, 1, 0}, 0);
  const std::vector<SafeInterval>& iv = table.Intervals(1);
  ASSERT_EQ(iv.size(), 3u);
  EXPECT_EQ(iv[1].begin_step, 1);
  EXPECT_EQ(iv[1].end_step, 2);
  EXPECT_EQ(iv[1].conflicts, 2);
  EXPECT_EQ(iv[0].conflicts + iv[2].conflicts, 0);
  EXPECT_EQ(table.SoftEdgeConflicts(1, 0, 1), 1);
  table.Clear();
  EXPECT_EQ(table.Intervals(1).size(), 1u);
  EXPECT_EQ(table.SoftEdgeConflicts(1, 0, 1), 0);
}

TEST(SippTest, ShortestPathWithoutReservations) {
  const GridGraph g(InlineMap(".....\n", 5, 1));
  ConstraintTable table(g.size());
  DistanceTable dist(g, g.VertexAt(4, 0));
  SippPlanner sipp(g);
  absl::StatusOr<SippResult> r = sipp.Plan({g.VertexAt(0, 0), g.VertexAt(4, 0)}, table, dist);
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->arrival_step, 4);
  EXPECT_EQ(r->path.size(), 5u);
  EXPECT_EQ(r->conflicts, 0);
}

TEST(SippTest, WaitsForAHardPathToClearTheCorridor) {
  // A robot crosses the corridor's middle cell at steps 1–3 going down; ours must wait.
  const GridGraph g(InlineMap("@.@\n...\n@.@\n@.@\n", 3, 4));
  ConstraintTable table(g.size());
  table.AddHardPath({g.VertexAt(1, 0), g.VertexAt(1, 1), g.VertexAt(1, 2), g.VertexAt(1, 3)}, 0);
  DistanceTable dist(g, g.VertexAt(2, 1));
  SippPlanner sipp(g);
  absl::StatusOr<SippResult> r = sipp.Plan({g.VertexAt(0, 1), g.VertexAt(2, 1)}, table, dist);
  ASSERT_TRUE(r.ok()) << r.status();
  // The middle cell is taken at step 1 only; arriving there at 2 and at the goal at 3 is
  // the earliest.
  EXPECT_EQ(r->arrival_step, 3);
  ASSERT_GE(r->path.size(), 2u);
  EXPECT_NE(r->path[1], g.VertexAt(1, 1));
}

TEST(SippTest, NeverTakesAHardStepOrSwap) {
  const GridGraph g(InlineMap("....\n", 4, 1));
  ConstraintTable table(g.size());
  // Another robot walks 3 → 2 → 1 and parks at 1... our robot starting at 0 cannot reach 3.
  table.AddHardPath({3, 2, 1}, 0);
  DistanceTable dist(g, 3);
  SippPlanner sipp(g);
  EXPECT_EQ(sipp.Plan({0, 3}, table, dist).status().code(), absl::StatusCode::kNotFound);
}

TEST(SippTest, AvoidsSoftConflictsWhenACostFreeDetourExists) {
  // Two parallel lanes; the soft path occupies the lower lane. Both routes are 4 moves long.
  const GridGraph g(InlineMap("...\n.@.\n...\n", 3, 3));
  ConstraintTable table(g.size());
  table.AddSoftPath({g.VertexAt(1, 2), g.VertexAt(1, 2), g.VertexAt(1, 2), g.VertexAt(1, 2)}, 0,
                    /*park=*/true);
  DistanceTable dist(g, g.VertexAt(2, 0));
  SippPlanner sipp(g);
  SippRequest req{g.VertexAt(0, 2), g.VertexAt(2, 0)};
  absl::StatusOr<SippResult> r = sipp.Plan(req, table, dist);
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->arrival_step, 4);
  EXPECT_EQ(r->conflicts, 0);
}

TEST(SippTest, GoalIsReachedOnlyWhereTheAgentMayStay) {
  // The goal is reserved at step 6; the agent arrives later even though 2 moves would do.
  const GridGraph g(InlineMap("...\n", 3, 1));
  ConstraintTable table(g.size());
  table.AddHardVertex(2, 6);
  DistanceTable dist(g, 2);
  SippPlanner sipp(g);
  absl::StatusOr<SippResult> r = sipp.Plan({0, 2}, table, dist);
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->arrival_step, 7);
  EXPECT_NE(r->path[6], 2);
  EXPECT_EQ(r->path.back(), 2);
}

TEST(SippTest, WithNoFollowingItNeverEntersAVertexTakenTheStepBefore) {
  // Another robot leaves vertex 1 for 2 at step 1; ours, at 0, wants to reach 3.
  const GridGraph g(InlineMap("....\n", 4, 1));
  ConstraintTable table(g.size());
  table.AddHardPath({1, 2, 3, 3}, 0, /*park=*/false);
  DistanceTable dist(g, 3);
  SippPlanner sipp(g);
  SippRequest req{0, 3};
  absl::StatusOr<SippResult> follows = sipp.Plan(req, table, dist);
  ASSERT_TRUE(follows.ok()) << follows.status();
  EXPECT_EQ(follows->arrival_step, 4);  // right behind the other robot, then 3 once it is free
  req.no_following = true;
  absl::StatusOr<SippResult> apart = sipp.Plan(req, table, dist);
  ASSERT_TRUE(apart.ok()) << apart.status();
  for (size_t k = 1; k < apart->path.size(); ++k) {
    if (apart->path[k] == apart->path[k - 1]) continue;
    // The vertex entered at step k was free at step k - 1: the other robot holds 1 at step 0, 2
    // at 1, 3 at 2 and 3, nothing later.
    const std::vector<int> other = {1, 2, 3, 3};
    if (k - 1 < other.size()) {
      EXPECT_NE(apart->path[k], other[k - 1]) << "step " << k;
    }
  }
  EXPECT_EQ(apart->arrival_step, 5);
}

TEST(SippTest, StartsAtTheGivenStep) {
  const GridGraph g(InlineMap("...\n", 3, 1));
  ConstraintTable table(g.size());
  DistanceTable dist(g, 2);
  SippPlanner sipp(g);
  SippRequest req{0, 2, /*start_step=*/5};
  absl::StatusOr<SippResult> r = sipp.Plan(req, table, dist);
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->arrival_step, 7);
  EXPECT_EQ(r->path.size(), 3u);
  table.AddHardVertex(0, 5);
  EXPECT_EQ(sipp.Plan(req, table, dist).status().code(), absl::StatusCode::kNotFound);
}

}  // namespace
}  // namespace fleetnav::planner
