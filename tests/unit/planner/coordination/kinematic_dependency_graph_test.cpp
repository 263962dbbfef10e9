#include "fleetnav/planner/coordination/kinematic_dependency_graph.hpp"

#include <gtest/gtest.h>

#include <random>

#include "kinematic_fleet.hpp"
#include "test_maps.hpp"

namespace fleetnav::planner {
namespace {

using testing::InlineMap;
using testing::RandomMixedFleet;

struct Outcome {
  bool overlap_free = true;
  bool deadlocked = false;
  bool all_at_goal = false;
};

// Executes the plan's actions with seeded random delays: an action starts when the robot's
// previous action and (with `use_dependencies`) all its cross-robot dependencies are finished,
// and takes 1 tick plus, with probability `delay_probability`, 1–`max_delay` more. A robot
// covers both footprints while acting. Checks every tick for overlapping robots.
Outcome Execute(const KinematicMapfProblem& problem, const KinematicDependencyGraph& kdg,
                uint64_t seed, bool use_dependencies, double delay_probability = 0.3,
                int max_delay = 4) {
  std::mt19937_64 rng(seed);
  std::bernoulli_distribution delayed(delay_probability);
  std::uniform_int_distribution<int> extra(1, max_delay);
  const int n = static_cast<int>(problem.robots.size());
  std::vector<size_t> next(n, 0);
  std::vector<int> busy(n, -1), remaining(n, 0);
  std::vector<bool> finished(kdg.graph().num_actions(), false);
  std::vector<GridState> at(n);
  for (int r = 0; r < n; ++r) {
    at[r] = {problem.robots[r].start_x, problem.robots[r].start_y, problem.robots[r].start_heading};
  }
  Outcome out;
  std::vector<int> cells, more;
  for (int tick = 0; tick < 100000; ++tick) {
    bool any_left = false, any_busy = false;
    for (int r = 0; r < n; ++r) {
      const std::vector<int>& mine = kdg.graph().ActionsOf(r);
      if (busy[r] < 0 && next[r] < mine.size()) {
        const int a = mine[next[r]];
        bool ready = true;
        if (use_dependencies) {
          for (int d : kdg.graph().DependenciesOf(a)) ready &= finished[d];
        }
        if (ready) {
          busy[r] = a;
          remaining[r] = 1 + (delayed(rng) ? extra(rng) : 0);
        }
      }
    }
    // Coverage this tick.
    std::vector<int> owner(problem.map->width * problem.map->height, -1);
    for (int r = 0; r < n; ++r) {
      CoveredCells(*problem.map, problem.robots[r].motion, at[r], &cells);
      if (busy[r] >= 0) {
        CoveredCells(*problem.map, problem.robots[r].motion, kdg.action(busy[r]).to, &more);
        cells.insert(cells.end(), more.begin(), more.end());
      }
      for (int c : cells) {
        if (owner[c] >= 0 && owner[c] != r) out.overlap_free = false;
        owner[c] = r;
      }
    }
    for (int r = 0; r < n; ++r) {
      if (busy[r] >= 0 && --remaining[r] == 0) {
        finished[busy[r]] = true;
        at[r] = kdg.action(busy[r]).to;
        busy[r] = -1;
        ++next[r];
      }
      any_busy |= busy[r] >= 0;
      any_left |= next[r] < kdg.graph().ActionsOf(r).size();
    }
    if (!any_left) {
      out.all_at_goal = true;
      for (int r = 0; r < n; ++r) {
        out.all_at_goal &=
            at[r].x == problem.robots[r].goal_x && at[r].y == problem.robots[r].goal_y;
      }
      return out;
    }
    if (!any_busy && tick > 0) {
      // Nothing running and nothing could start this tick: check whether anything can start.
      bool startable = false;
      for (int r = 0; r < n; ++r) {
        if (next[r] >= kdg.graph().ActionsOf(r).size()) continue;
        bool ready = true;
        for (int d : kdg.graph().DependenciesOf(kdg.graph().ActionsOf(r)[next[r]]))
          ready &= finished[d];
        startable |= ready || !use_dependencies;
      }
      if (!startable) {
        out.deadlocked = true;
        return out;
      }
    }
  }
  out.deadlocked = true;
  return out;
}

TEST(KinematicDependencyGraphTest, TheBaySwapRunsSafelyUnderDelays) {
  const MovingAiMap map = testing::BayAlley();
  const KinematicMapfProblem problem = testing::BaySwap(map);
  const KinematicMapfPlan plan = PlanKinematicMapf(problem, {}).value();
  absl::StatusOr<KinematicDependencyGraph> kdg = KinematicDependencyGraph::Compile(problem, plan);
  ASSERT_TRUE(kdg.ok()) << kdg.status();
  EXPECT_GT(kdg->graph().num_cross_dependencies(), 0);
  for (uint64_t seed = 0; seed < 20; ++seed) {
    const Outcome out = Execute(problem, *kdg, seed, /*use_dependencies=*/true);
    EXPECT_TRUE(out.overlap_free) << "seed " << seed;
    EXPECT_FALSE(out.deadlocked) << "seed " << seed;
    EXPECT_TRUE(out.all_at_goal) << "seed " << seed;
  }
}

TEST(KinematicDependencyGraphTest, RefusesAnInvalidPlan) {
  const MovingAiMap map = InlineMap("......\n", 6, 1);
  KinematicMapfProblem problem{&map, {{0, 0, kPlusX, 2, 0, -1, GridMotionModel{}}}};
  EXPECT_EQ(KinematicDependencyGraph::Compile(problem, {{{{0, 0, 0}, {2, 0, 0}}}}).status().code(),
            absl::StatusCode::kInvalidArgument);
}

class KinematicDelayTest : public ::testing::TestWithParam<uint64_t> {};

// A mixed fleet (forward-only, omni and 2 x 2 robots) is planned, validated, and executed with
// random delays: never an overlap, never a deadlock, everyone home.
TEST_P(KinematicDelayTest, MixedFleetIsPlannedAndNeverOverlapsUnderDelays) {
  const MovingAiMap map = testing::Random32Map10();
  const KinematicMapfProblem problem = RandomMixedFleet(map, GetParam());
  ASSERT_EQ(problem.robots.size(), 8u);
  KinematicMapfParams params;
  params.seed = GetParam();
  params.time_limit_s = 5.0;
  absl::StatusOr<KinematicMapfPlan> plan = PlanKinematicMapf(problem, params);
  ASSERT_TRUE(plan.ok()) << plan.status();
  ASSERT_TRUE(ValidateKinematicPlan(problem, *plan).ok()) << ValidateKinematicPlan(problem, *plan);
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(testing::NeverReverses(plan->states[i]));
  absl::StatusOr<KinematicDependencyGraph> kdg = KinematicDependencyGraph::Compile(problem, *plan);
  ASSERT_TRUE(kdg.ok()) << kdg.status();
  for (uint64_t seed = 0; seed < 10; ++seed) {
    const Outcome out = Execute(problem, *kdg, GetParam() * 100 + seed, true);
    EXPECT_TRUE(out.overlap_free) << "delay seed " << seed;
    EXPECT_FALSE(out.deadlocked) << "delay seed " << seed;
    EXPECT_TRUE(out.all_at_goal) << "delay seed " << seed;
  }
}

INSTANTIATE_TEST_SUITE_P(Seeds, KinematicDelayTest, ::testing::Values(1, 2, 3, 4, 5));

// Control: without the cross-robot dependencies the same kind of delays make robots overlap.
TEST(KinematicDelayTest, WithoutTheDependenciesDelaysCauseOverlaps) {
  const MovingAiMap map = testing::BayAlley();
  const KinematicMapfProblem problem = testing::BaySwap(map);
  const KinematicMapfPlan plan = PlanKinematicMapf(problem, {}).value();
  const KinematicDependencyGraph kdg = KinematicDependencyGraph::Compile(problem, plan).value();
  int overlapping_runs = 0;
  for (uint64_t seed = 0; seed < 20; ++seed) {
    overlapping_runs += !Execute(problem, kdg, seed, /*use_dependencies=*/false).overlap_free;
  }
  EXPECT_GT(overlapping_runs, 0);
}

}  // namespace
}  // namespace fleetnav::planner
