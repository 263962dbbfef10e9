#include "fleetnav/planner/kinematic/kinematic_mapf.hpp"

#include <gtest/gtest.h>

#include "kinematic_fleet.hpp"
#include "test_maps.hpp"

namespace fleetnav::planner {
namespace {

using testing::ForwardOnly;
using testing::InlineMap;
using testing::Square2x2;

TEST(KinematicMapfTest, TwoForwardOnlyRobotsSwapThroughTheBay) {
  // A barn alley with one bay; the robots face each other and may not reverse, so one drives
  // into the bay, turns round in it and comes out after the other has passed.
  const MovingAiMap map = testing::BayAlley();
  const KinematicMapfProblem problem = testing::BaySwap(map);
  absl::StatusOr<KinematicMapfPlan> plan = PlanKinematicMapf(problem, {});
  ASSERT_TRUE(plan.ok()) << plan.status();
  EXPECT_TRUE(ValidateKinematicPlan(problem, *plan).ok()) << ValidateKinematicPlan(problem, *plan);
  for (const auto& states : plan->states) EXPECT_TRUE(testing::NeverReverses(states));
  bool used_bay = false;
  for (const auto& states : plan->states) {
    for (const GridState& s : states) used_bay |= s.y == 0;
  }
  EXPECT_TRUE(used_bay);
}

TEST(KinematicMapfTest, TheBudgetIsWorkSoAnExhaustedSearchSaysSoInsteadOfAnotherPlan) {
  // Prioritized planning alone cannot swap through the bay: with no conflict-based search
  // nodes and two priority orders the search ends ResourceExhausted, whatever the machine's
  // load; with the default budget the same problem is solved.
  const MovingAiMap map = testing::BayAlley();
  const KinematicMapfProblem problem = testing::BaySwap(map);
  KinematicMapfParams params;
  params.cbs_max_nodes = 0;
  params.max_priority_orders = 2;
  const absl::Status exhausted = PlanKinematicMapf(problem, params).status();
  EXPECT_EQ(exhausted.code(), absl::StatusCode::kResourceExhausted) << exhausted;
  EXPECT_NE(exhausted.message().find("2 priority orders"), std::string::npos) << exhausted;
  params.max_priority_orders = 0;
  EXPECT_EQ(PlanKinematicMapf(problem, params).status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_TRUE(PlanKinematicMapf(problem, {}).ok());
}

TEST(KinematicMapfTest, OneWayLanesSendTheRobotTheLongWayRound) {
  // A ring; lanes run counter-clockwise (+x along the top row, +y down the right column, −x
  // along the bottom, −y up the left). The goal lies one cell against the lanes.
  const MovingAiMap map = InlineMap(
      "....\n"
      ".@@.\n"
      "....\n",
      4, 3);
  GridMotionModel lanes;
  lanes.allowed_moves.assign(12, 0);
  auto allow = [&](int x, int y, int d) { lanes.allowed_moves[y * 4 + x] |= 1 << d; };
  for (int x = 0; x < 3; ++x) allow(x, 0, kPlusX);
  for (int y = 0; y < 2; ++y) allow(3, y, kPlusY);
  for (int x = 3; x > 0; --x) allow(x, 2, kMinusX);
  for (int y = 2; y > 0; --y) allow(0, y, kMinusY);
  KinematicMapfProblem problem{&map, {{1, 0, kPlusX, 0, 0, -1, lanes}}};
  absl::StatusOr<KinematicMapfPlan> plan = PlanKinematicMapf(problem, {});
  ASSERT_TRUE(plan.ok()) << plan.status();
  EXPECT_TRUE(ValidateKinematicPlan(problem, *plan).ok());
  EXPECT_EQ(plan->states[0].size(), 10u);  // nine moves round the ring
}

TEST(KinematicMapfTest, SquareFootprintsNeverOverlap) {
  const MovingAiMap map = InlineMap(
      "......\n"
      "......\n"
      "......\n"
      "......\n"
      "......\n",
      6, 5);
  KinematicMapfProblem problem{&map, {}};
  problem.robots.push_back({0, 0, kPlusX, 4, 3, -1, Square2x2()});
  problem.robots.push_back({4, 3, kPlusX, 0, 0, -1, Square2x2()});
  problem.robots.push_back({4, 0, kPlusX, 0, 3, -1, Square2x2()});
  absl::StatusOr<KinematicMapfPlan> plan = PlanKinematicMapf(problem, {});
  ASSERT_TRUE(plan.ok()) << plan.status();
  ASSERT_TRUE(ValidateKinematicPlan(problem, *plan).ok()) << ValidateKinematicPlan(problem, *plan);
  size_t horizon = 0;
  for (const auto& s : plan->states) horizon = std::max(horizon, s.size());
  auto at = [&](int i, size_t t) {
    const auto& s = plan->states[i];
    return t < s.size() ? s[t] : s.back();
  };
  for (size_t t = 0; t < horizon; ++t) {
    for (int i = 0; i < 3; ++i) {
      for (int j = i + 1; j < 3; ++j) {
        const GridState a = at(i, t), b = at(j, t);
        EXPECT_TRUE(std::abs(a.x - b.x) >= 2 || std::abs(a.y - b.y) >= 2)
            << "robots " << i << " and " << j << " at step " << t;
      }
    }
  }
}

TEST(KinematicMapfTest, ValidatorCatchesOverlapsAndForbiddenMoves) {
  const MovingAiMap map = InlineMap("......\n......\n", 6, 2);
  KinematicMapfProblem squares{&map, {}};
  squares.robots.push_back({0, 0, kPlusX, 1, 0, -1, Square2x2()});
  squares.robots.push_back({3, 0, kPlusX, 2, 0, -1, Square2x2()});
  absl::Status overlap =
      ValidateKinematicPlan(squares, {{{{0, 0, 0}, {1, 0, 0}}, {{3, 0, 0}, {2, 0, 0}}}});
  EXPECT_EQ(overlap.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(overlap.message().find("overlap"), std::string::npos) << overlap;

  KinematicMapfProblem lely{&map, {{3, 0, kPlusX, 2, 0, -1, ForwardOnly()}}};
  absl::Status reverse = ValidateKinematicPlan(lely, {{{{3, 0, kPlusX}, {2, 0, kPlusX}}}});
  EXPECT_EQ(reverse.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(reverse.message().find("motion model"), std::string::npos) << reverse;
}

TEST(KinematicMapfTest, RejectsBadProblemsNamingTheRobot) {
  const MovingAiMap map = InlineMap("..@\n...\n", 3, 2);
  auto code_of = [&](const GridRobot& r) {
    KinematicMapfProblem p{&map, {r}};
    return PlanKinematicMapf(p, {}).status();
  };
  // Footprint on the obstacle, bad heading, wrong lane mask size, unreachable goal.
  EXPECT_EQ(code_of({1, 0, kPlusX, 0, 1, -1, Square2x2()}).code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(code_of({0, 0, 7, 0, 1, -1, ForwardOnly()}).code(), absl::StatusCode::kInvalidArgument);
  GridMotionModel bad_lanes;
  bad_lanes.allowed_moves = {1, 1};
  EXPECT_EQ(code_of({0, 0, kPlusX, 0, 1, -1, bad_lanes}).code(),
            absl::StatusCode::kInvalidArgument);
  GridMotionModel no_moves;
  no_moves.allowed_moves.assign(6, 0);
  absl::Status unreachable = code_of({0, 0, kPlusX, 0, 1, -1, no_moves});
  EXPECT_EQ(unreachable.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(unreachable.message().find("robots[0].goal"), std::string::npos) << unreachable;
}

}  // namespace
}  // namespace fleetnav::planner
