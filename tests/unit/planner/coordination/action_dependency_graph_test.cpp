#include "fleetnav/planner/coordination/action_dependency_graph.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <random>

#include "fleetnav/planner/mapf/eecbs.hpp"
#include "fleetnav/planner/mapf/lacam.hpp"
#include "fleetnav/planner/mapf/mapf_planner.hpp"
#include "test_maps.hpp"

namespace fleetnav::planner {
namespace {

using ::testing::HasSubstr;
using testing::InlineMap;

// Executes an ADG in discrete ticks. Each move lasts 1 tick plus, with probability
// `delay_probability`, a seeded random delay of 1..max_delay ticks; a moving robot holds both
// ends of its move. Every tick asserts that no cell is held by two robots.
struct ExecutionOutcome {
  bool collision_free = true;
  bool deadlocked = false;
  bool all_at_goal = false;
  int ticks = 0;
  int delayed_actions = 0;
};

ExecutionOutcome ExecuteWithDelays(const MapfInstance& inst, const ActionDependencyGraph& adg,
                                   uint64_t seed, double delay_probability, int max_delay) {
  std::mt19937_64 rng(seed);
  std::bernoulli_distribution delayed(delay_probability);
  std::uniform_int_distribution<int> extra(1, max_delay);
  const int n = inst.num_agents();
  std::vector<int> position = inst.starts;
  std::vector<size_t> next(n, 0);    // index into ActionsOf(i) of the next action
  std::vector<int> remaining(n, 0);  // ticks left of the running action, 0 if idle
  std::vector<bool> done(adg.graph().num_actions(), false);
  std::vector<int> holder(inst.graph->size(), -1);
  ExecutionOutcome out;
  for (int tick = 0; tick < 100000; ++tick) {
    // Finish running moves.
    for (int i = 0; i < n; ++i) {
      if (remaining[i] > 0 && --remaining[i] == 0) {
        const int id = adg.graph().ActionsOf(i)[next[i]];
        done[id] = true;
        position[i] = adg.action(id).to;
        ++next[i];
      }
    }
    // Start every action whose dependencies are finished.
    bool any_running = false;
    for (int i = 0; i < n; ++i) {
      if (remaining[i] == 0 && next[i] < adg.graph().ActionsOf(i).size()) {
        const int id = adg.graph().ActionsOf(i)[next[i]];
        bool ready = true;
        for (int d : adg.graph().DependenciesOf(id)) ready = ready && done[d];
        if (ready) {
          const bool late = delayed(rng);
          out.delayed_actions += late;
          remaining[i] = 1 + (late ? extra(rng) : 0);
        }
      }
      any_running = any_running || remaining[i] > 0;
    }
    // Occupancy check: an idle robot holds its cell, a moving one both ends.
    std::fill(holder.begin(), holder.end(), -1);
    for (int i = 0; i < n; ++i) {
      std::vector<int> cells = {position[i]};
      if (remaining[i] > 0) cells.push_back(adg.action(adg.graph().ActionsOf(i)[next[i]]).to);
      for (int c : cells) {
        if (holder[c] != -1 && holder[c] != i) out.collision_free = false;
        holder[c] = i;
      }
    }
    out.ticks = tick;
    if (!any_running) {
      bool finished = true;
      for (int i = 0; i < n; ++i) finished = finished && next[i] == adg.graph().ActionsOf(i).size();
      out.deadlocked = !finished;
      break;
    }
  }
  out.all_at_goal = position == inst.goals;
  return out;
}

TEST(AdgTest, CompilesMovesAndCrossDependencies) {
  // Agent 0 moves along the row first; agent 1 follows into the cells it leaves.
  const GridGraph g(InlineMap("....\n", 4, 1));
  MapfInstance inst{&g, {1, 0}, {3, 2}};
  MapfSolution sol{{{1, 2, 3}, {0, 1, 2}}};
  absl::StatusOr<ActionDependencyGraph> adg = ActionDependencyGraph::Compile(inst, sol);
  ASSERT_TRUE(adg.ok()) << adg.status();
  EXPECT_EQ(adg->graph().num_actions(), 4);
  EXPECT_EQ(adg->graph().num_cross_dependencies(), 2);
  // Agent 1's move into cell 1 waits for agent 0's move out of it.
  const int enter1 = adg->graph().ActionsOf(1)[0];
  EXPECT_THAT(adg->graph().DependenciesOf(enter1),
              ::testing::Contains(adg->graph().ActionsOf(0)[0]));
}

TEST(AdgTest, WaitsAreNotActions) {
  const GridGraph g(InlineMap("...\n", 3, 1));
  MapfInstance inst{&g, {0}, {2}};
  absl::StatusOr<ActionDependencyGraph> adg =
      ActionDependencyGraph::Compile(inst, {{{0, 0, 1, 1, 2}}});
  ASSERT_TRUE(adg.ok());
  EXPECT_EQ(adg->graph().num_actions(), 2);
  EXPECT_EQ(adg->action(1).planned_step, 4);
}

TEST(AdgTest, RefusesInvalidPlansAndRotations) {
  const GridGraph g(InlineMap("..\n..\n", 2, 2));
  const int a = g.VertexAt(0, 0), b = g.VertexAt(1, 0), c = g.VertexAt(1, 1), d = g.VertexAt(0, 1);
  MapfInstance bad{&g, {a}, {c}};
  EXPECT_EQ(ActionDependencyGraph::Compile(bad, {{{a, c}}}).status().code(),
            absl::StatusCode::kInvalidArgument);
  // Four robots rotate one step around the 2 x 2 block.
  MapfInstance rot{&g, {a, b, c, d}, {b, c, d, a}};
  absl::StatusOr<ActionDependencyGraph> adg =
      ActionDependencyGraph::Compile(rot, {{{a, b}, {b, c}, {c, d}, {d, a}}});
  EXPECT_EQ(adg.status().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_THAT(std::string(adg.status().message()), HasSubstr("rotation"));
}

class AdgDelayTest : public ::testing::TestWithParam<uint64_t> {};

TEST_P(AdgDelayTest, FiftyRobotsWithRandomDelaysNeverCollideAndAllArrive) {
  absl::StatusOr<MovingAiMap> map = testing::Random32Map20();
  ASSERT_TRUE(map.ok()) << map.status();
  const GridGraph g(*map);
  absl::StatusOr<MapfInstance> inst = RandomInstance(g, 50, GetParam());
  ASSERT_TRUE(inst.ok());
  MapfPlannerParams params;
  params.seed = GetParam();
  params.forbid_rotations = true;
  absl::StatusOr<MapfResult> plan = MapfPlanner(params).Solve(*inst, MapfStopCondition{0.5});
  ASSERT_TRUE(plan.ok()) << plan.status();
  absl::StatusOr<ActionDependencyGraph> adg = ActionDependencyGraph::Compile(*inst, plan->solution);
  ASSERT_TRUE(adg.ok()) << adg.status();
  EXPECT_GT(adg->graph().num_cross_dependencies(), 0);
  for (uint64_t delay_seed = 0; delay_seed < 4; ++delay_seed) {
    const ExecutionOutcome out =
        ExecuteWithDelays(*inst, *adg, GetParam() * 100 + delay_seed, 0.3, 5);
    EXPECT_TRUE(out.collision_free) << "delay seed " << delay_seed;
    EXPECT_FALSE(out.deadlocked) << "delay seed " << delay_seed;
    EXPECT_TRUE(out.all_at_goal) << "delay seed " << delay_seed;
    EXPECT_GT(out.delayed_actions, 0);
  }
}

INSTANTIATE_TEST_SUITE_P(Seeds, AdgDelayTest, ::testing::Values(21, 22, 23, 24, 25));

TEST(AdgDelayTest, WithoutTheGraphDelaysCauseCollisions) {
  // Control experiment: the same plans executed step by step with the same delays but no
  // cross-robot dependencies do collide, so the delay test above is not vacuous.
  absl::StatusOr<MovingAiMap> map = testing::Random32Map20();
  ASSERT_TRUE(map.ok()) << map.status();
  const GridGraph g(*map);
  absl::StatusOr<MapfInstance> inst = RandomInstance(g, 50, 21);
  ASSERT_TRUE(inst.ok());
  absl::StatusOr<MapfResult> plan =
      EecbsSolver(EecbsParams{1.2}).Solve(*inst, MapfStopCondition{10.0});
  ASSERT_TRUE(plan.ok()) << plan.status();
  absl::StatusOr<ActionDependencyGraph> adg = ActionDependencyGraph::Compile(*inst, plan->solution);
  ASSERT_TRUE(adg.ok());
  int collisions = 0;
  for (uint64_t seed = 0; seed < 4; ++seed) {
    // Strip the cross-robot dependencies by executing each robot's moves on its own clock.
    ExecutionOutcome out;
    std::mt19937_64 rng(seed);
    std::bernoulli_distribution delayed(0.3);
    const int n = inst->num_agents();
    std::vector<int> ready_at(n, 0);
    std::vector<size_t> next(n, 0);
    std::vector<int> position = inst->starts;
    for (int tick = 0; tick < 2000; ++tick) {
      std::vector<int> holder(g.size(), -1);
      for (int i = 0; i < n; ++i) {
        if (next[i] < adg->graph().ActionsOf(i).size() && tick >= ready_at[i]) {
          const AdgAction& a = adg->action(adg->graph().ActionsOf(i)[next[i]]);
          if (tick >= a.planned_step - 1) {
            position[i] = a.to;
            ++next[i];
            ready_at[i] = tick + 1 + (delayed(rng) ? 3 : 0);
          }
        }
      }
      for (int i = 0; i < n; ++i) {
        if (holder[position[i]] != -1) out.collision_free = false;
        holder[position[i]] = i;
      }
    }
    collisions += !out.collision_free;
  }
  EXPECT_GT(collisions, 0);
}

}  // namespace
}  // namespace fleetnav::planner
