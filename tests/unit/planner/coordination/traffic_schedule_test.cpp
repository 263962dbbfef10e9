#include "fleetnav/planner/coordination/traffic_schedule.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "absl/strings/str_cat.h"
#include "coordination/square_routes.hpp"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/planner/coordination/route_prediction.hpp"

namespace fleetnav::planner {
namespace {

using testing::At;
using testing::kSquare;
using testing::Line;
using testing::Route;

TEST(CellSetTest, SweepCoversTheFootprintAndSetsIntersectOnlyWhenTheyShareCells) {
  const CellSet a = Line({0, 0}, {4, 0});
  EXPECT_TRUE(a.Intersects(At({4.2, 0})));
  EXPECT_FALSE(a.Intersects(At({0, 2.0})));
  // A margin grows the region: a square 0.6 m away is touched with a 0.6 m margin.
  const CellSet grown = CellSet::Sweep({Pose2(0, 0, 0)}, kSquare, 0.6, 0.25);
  EXPECT_TRUE(grown.Intersects(At({0, 1.6})));
  EXPECT_FALSE(grown.Intersects(At({0, 3.0})));
}

TEST(CellSetTest, ASweepHoldsEachCellOnceAndExactlyTheCellsOfItsPoses) {
  // A pose repeated adds no cell: each cell is stored once.
  const CellSet once = CellSet::Sweep({Pose2(1.0, 2.0, 0.3)}, kSquare, 0.2, 0.25);
  const CellSet repeated =
      CellSet::Sweep(std::vector<Pose2>(10, Pose2(1.0, 2.0, 0.3)), kSquare, 0.2, 0.25);
  EXPECT_EQ(repeated.size(), once.size());
  // A sweep along a curve touches a probe exactly when one of its poses alone does.
  std::vector<Pose2> poses;
  for (int i = 0; i <= 40; ++i) poses.emplace_back(0.1 * i, std::sin(0.1 * i), 0.05 * i);
  const CellSet swept = CellSet::Sweep(poses, kSquare, 0.1, 0.25);
  size_t sum_of_sizes = 0;
  std::vector<CellSet> alone;
  for (const Pose2& pose : poses) {
    alone.push_back(CellSet::Sweep({pose}, kSquare, 0.1, 0.25));
    sum_of_sizes += alone.back().size();
  }
  EXPECT_LT(swept.size(), sum_of_sizes / 4);  // neighbouring poses share most cells
  const std::vector<Eigen::Vector2d> dot{{-0.01, -0.01}, {0.01, -0.01}, {0.01, 0.01}};
  int touched = 0;
  for (double x = -1.5; x <= 5.5; x += 0.125) {
    for (double y = -2.5; y <= 2.5; y += 0.125) {
      const CellSet probe = CellSet::Sweep({Pose2(x, y, 0.0)}, dot, 0.0, 0.25);
      bool any = false;
      for (const CellSet& one : alone) any = any || one.Intersects(probe);
      ASSERT_EQ(swept.Intersects(probe), any) << "probe at " << x << ", " << y;
      touched += any ? 1 : 0;
    }
  }
  EXPECT_GT(touched, 100);
}

TEST(TrafficScheduleTest, CrossingRoutesGoOneAfterTheOtherInExpectedOrder) {
  // a drives east along y = 0 through x = 0 first (t 0–10); b comes south later (t 10–20)
  // across the same place.
  ScheduledRoute a = Route("a", {{-5, 0}, {5, 0}, {5, -5}}, 0.0);
  ScheduledRoute b = Route("b", {{0, 8}, {0, 4}, {0, -4}}, 0.0);
  std::vector<TrafficClearanceDecision> d = DecideClearances({a, b}, {});
  ASSERT_EQ(d.size(), 2u);
  EXPECT_EQ(d[0].cleared_up_to, 1);  // a: nothing holds it
  EXPECT_TRUE(d[0].waits.empty());
  EXPECT_EQ(d[1].cleared_up_to, 0);  // b: may approach, not cross
  ASSERT_EQ(d[1].waits.size(), 1u);
  EXPECT_EQ(d[1].waits[0].blocker_robot_id, "a");
  EXPECT_EQ(d[1].waits[0].blocker_action, 0);
  // Once a has left the crossing, b may cross; its clearance is kept when a is late.
  a.first_unfinished = 1;
  a.cleared_up_to = 1;
  b.cleared_up_to = 0;
  d = DecideClearances({a, b}, {});
  EXPECT_EQ(d[1].cleared_up_to, 1);
  EXPECT_TRUE(d[1].waits.empty());
  EXPECT_FALSE(d[0].deadlocked);
}

TEST(TrafficScheduleTest, ARobotThatStopsInsideACrossingIsWaitedForUntilItHasLeftIt) {
  // a's first action ends on the crossing and its second leaves it: b waits for the second,
  // for a would stand in b's way between the two.
  ScheduledRoute a = Route("a", {{-5, 0}, {0, 0}, {5, 0}}, 0.0);
  ScheduledRoute b = Route("b", {{0, 5}, {0, -5}}, 5.0);
  std::vector<TrafficClearanceDecision> d = DecideClearances({a, b}, {});
  EXPECT_EQ(d[0].cleared_up_to, 1);
  EXPECT_EQ(d[1].cleared_up_to, -1);
  ASSERT_EQ(d[1].waits.size(), 1u);
  EXPECT_EQ(d[1].waits[0].blocker_robot_id, "a");
  EXPECT_EQ(d[1].waits[0].blocker_action, 1);
}

TEST(TrafficScheduleTest, ClearedActionsComeFirstWhateverTheExpectedTimes) {
  // b was cleared into the crossing before a's route was known: a waits, though its expected
  // time is earlier.
  ScheduledRoute a = Route("a", {{-5, 0}, {5, 0}}, 0.0);
  ScheduledRoute b = Route("b", {{0, 5}, {0, -5}}, 100.0);
  b.cleared_up_to = 0;
  std::vector<TrafficClearanceDecision> d = DecideClearances({a, b}, {});
  EXPECT_EQ(d[0].cleared_up_to, -1);
  ASSERT_EQ(d[0].waits.size(), 1u);
  EXPECT_EQ(d[0].waits[0].blocker_robot_id, "b");
  EXPECT_EQ(d[1].cleared_up_to, 0);
}

TEST(TrafficScheduleTest, ARobotsRestingPlaceIsCrossedBeforeItArrives) {
  // b ends at (0, 0), on a's later leg: a must pass there before b's last action, although b
  // is expected earlier.
  ScheduledRoute a = Route("a", {{-8, 3}, {-4, 3}, {-4, 0}, {4, 0}}, 0.0);
  ScheduledRoute b = Route("b", {{0, -8}, {0, -4}, {0, 0}}, 0.0);
  std::vector<TrafficClearanceDecision> d = DecideClearances({a, b}, {});
  EXPECT_EQ(d[0].cleared_up_to, 2);
  EXPECT_EQ(d[1].cleared_up_to, 0);
  ASSERT_FALSE(d[1].waits.empty());
  EXPECT_EQ(d[1].waits[0].blocker_robot_id, "a");
  EXPECT_EQ(d[1].waits[0].blocker_action, 2);
}

TEST(TrafficScheduleTest, ARobotStandingAtItsStartIsPassedOnlyAfterItLeaves) {
  // b stands on a's path until b's first action; b's first action is expected later than a
  // passes, yet a waits for it.
  ScheduledRoute a = Route("a", {{-5, 0}, {5, 0}}, 0.0);
  ScheduledRoute b = Route("b", {{0, 0}, {0, 5}}, 50.0);
  std::vector<TrafficClearanceDecision> d = DecideClearances({a, b}, {});
  EXPECT_EQ(d[0].cleared_up_to, -1);
  ASSERT_EQ(d[0].waits.size(), 1u);
  EXPECT_EQ(d[0].waits[0].blocker_robot_id, "b");
  EXPECT_EQ(d[1].cleared_up_to, 0);
}

TEST(TrafficScheduleTest, ARobotStandingWhereAnotherClearedOneMustGoGoesFirst) {
  // a was cleared into the place where b stands (its first action), before b's route was
  // known: a may not go on through b. Holding b would leave both standing for good; b's way
  // out (north) does not pass where a stops, so b goes first and a follows it.
  ScheduledRoute a = Route("a", {{-5, 0}, {1.5, 0}, {8, 0}}, 0.0);
  a.cleared_up_to = 0;
  ScheduledRoute b = Route("b", {{3.5, 0}, {3.5, 5}}, 1.0);
  std::vector<TrafficClearanceDecision> d = DecideClearances({a, b}, {});
  EXPECT_EQ(d[0].cleared_up_to, 0);
  ASSERT_FALSE(d[0].waits.empty());
  EXPECT_EQ(d[0].waits[0].blocker_robot_id, "b");
  EXPECT_EQ(d[0].waits[0].blocker_action, 0);
  EXPECT_FALSE(d[1].deadlocked);
  EXPECT_EQ(d[1].cleared_up_to, 0);
  EXPECT_TRUE(d[1].waits.empty());
}

TEST(TrafficScheduleTest, ARobotStandingWhereAnotherMustGoIsHeldIfItsWayOutPassesWhereItStops) {
  // a was cleared north to (0, -1.5); b stands on a's next leg at (0, 1). b's way out to the
  // north-west goes first, a following it.
  ScheduledRoute a = Route("a", {{0, -5}, {0, -1.5}, {0, 8}}, 0.0);
  a.cleared_up_to = 0;
  ScheduledRoute b = Route("b", {{0, 1}, {-1.0, 2.5}, {-6, 2.5}}, 1.0);
  std::vector<TrafficClearanceDecision> d = DecideClearances({a, b}, {});
  EXPECT_FALSE(d[1].deadlocked);
  EXPECT_EQ(d[0].cleared_up_to, 0);
  ASSERT_FALSE(d[0].waits.empty());
  EXPECT_EQ(d[0].waits[0].blocker_robot_id, "b");
  // Where a stops after its cleared leg, b's first leg passes: b cannot go first after all.
  ScheduledRoute c = Route("c", {{0, 1}, {0, -3}, {-6, -3}}, 1.0);
  d = DecideClearances({a, c}, {});
  EXPECT_TRUE(d[1].deadlocked);
  EXPECT_EQ(d[1].cleared_up_to, -1);
  EXPECT_EQ(d[0].cleared_up_to, 0);
}

TEST(TrafficScheduleTest, OfACycleTheRobotStandingInAnothersWayIsNotTheOneHeld) {
  // w stands at (0, 0), where c ends; c, cleared down from the north, waits for w to leave;
  // w's way out to the north-east ends across b's way, so b passes there first; b, begun,
  // crosses c's way first and follows c, whose last leg ends at w. The three wait in a
  // cycle. Holding w (the only one not begun) would leave it standing where c must end: b,
  // the newer of the others, is held, and w goes.
  ScheduledRoute w = Route("w", {{0, 0}, {3, 4}}, 2.0);
  ScheduledRoute c = Route("c", {{0, 6}, {0, 3}, {0, 0}}, 0.0);
  c.cleared_up_to = 0;
  ScheduledRoute b = Route("b", {{-9, 3}, {-6, 3}, {0, 3}, {6, 3}}, 1.0);
  b.first_unfinished = 1;
  b.cleared_up_to = 0;
  std::vector<TrafficClearanceDecision> d = DecideClearances({w, c, b}, {});
  EXPECT_FALSE(d[0].deadlocked);
  EXPECT_EQ(d[0].cleared_up_to, 0);
  EXPECT_TRUE(d[2].deadlocked);
  EXPECT_FALSE(d[1].deadlocked);
}

TEST(TrafficScheduleTest, ParkedRobotsAreNeverDrivenThrough) {
  ScheduledRoute a = Route("a", {{-5, 0}, {-2, 0}, {5, 0}}, 0.0);
  std::vector<TrafficClearanceDecision> d =
      DecideClearances({a}, {ParkedRobot{"idle", At({2, 0})}});
  EXPECT_EQ(d[0].cleared_up_to, 0);
  ASSERT_EQ(d[0].waits.size(), 1u);
  EXPECT_EQ(d[0].waits[0].blocker_robot_id, "idle");
  EXPECT_EQ(d[0].waits[0].blocker_action, -1);
}

TEST(TrafficScheduleTest, RoutesThatEndOnEachOthersStartAreHeldNotDeadlocked) {
  // Each robot ends where the other starts: no order of whole actions works, so the newer
  // route is held and the older one runs.
  ScheduledRoute a = Route("a", {{0, 0}, {6, 0}}, 0.0);
  ScheduledRoute b = Route("b", {{6, 0}, {0, 0}}, 1.0);
  std::vector<TrafficClearanceDecision> d = DecideClearances({a, b}, {});
  EXPECT_FALSE(d[0].deadlocked);
  EXPECT_TRUE(d[1].deadlocked);
  EXPECT_EQ(d[1].cleared_up_to, -1);
}

TEST(TrafficScheduleTest, AHeldRobotStillDrivesWhatItWasClearedForAndNobodyIsClearedThroughIt) {
  // a was cleared for its first leg, north from (0, 0); its next leg, east along y = 6, meets b,
  // which stands at (6, 6) and ends at (8, 6): neither can go first, and a, the newer, is held.
  // a still drives its first leg: c, crossing that leg at y = 3, must wait for it.
  ScheduledRoute a = Route("a", {{0, 0}, {0, 6}, {10, 6}}, 5.0);
  a.cleared_up_to = 0;
  ScheduledRoute b = Route("b", {{14, 6}, {6, 6}, {8, 6}}, 0.0);
  b.first_unfinished = 1;
  b.cleared_up_to = 0;
  ScheduledRoute c = Route("c", {{-5, 3}, {5, 3}}, 1.0);
  std::vector<TrafficClearanceDecision> d = DecideClearances({a, b, c}, {});
  ASSERT_TRUE(d[0].deadlocked);
  EXPECT_EQ(d[0].cleared_up_to, 0);  // never taken back
  EXPECT_EQ(d[2].cleared_up_to, -1);
  ASSERT_FALSE(d[2].waits.empty());
  EXPECT_EQ(d[2].waits[0].blocker_robot_id, "a");
}

TEST(TrafficScheduleTest, AHeldRouteWaitsForTheRouteItCouldNotBeOrderedWithOnly) {
  // a and b swap places; c drives elsewhere. b is held for a, not for c: a circle of waits
  // through b (planner::FindWaitCycles) is one through a.
  ScheduledRoute a = Route("a", {{0, 0}, {6, 0}}, 0.0);
  ScheduledRoute b = Route("b", {{6, 0}, {0, 0}}, 1.0);
  ScheduledRoute c = Route("c", {{0, 20}, {6, 20}}, 0.5);
  std::vector<TrafficClearanceDecision> d = DecideClearances({a, b, c}, {});
  ASSERT_TRUE(d[1].deadlocked);
  ASSERT_EQ(d[1].waits.size(), 1u);
  EXPECT_EQ(d[1].waits[0].blocker_robot_id, "a");
  EXPECT_EQ(d[1].waits[0].blocker_action, 0);
}

TEST(TrafficScheduleTest, OfTwoRoutesThatCannotBothGoOnTheOneNotBegunIsHeldNotTheOneUnderWay) {
  // b is newer but has driven its first leg and stands at (6, 0), where a ends; a stands at
  // (0, 0), where b goes next. Holding b (the newer) would leave both standing for good: b
  // cannot drop its job. a has not begun: it is held, so it can be withdrawn and sent aside.
  ScheduledRoute a = Route("a", {{0, 0}, {6, 0}}, 0.0);
  ScheduledRoute b = Route("b", {{9, 0}, {6, 0}, {0, 0}}, 1.0);
  b.first_unfinished = 1;
  b.cleared_up_to = 0;
  std::vector<TrafficClearanceDecision> d = DecideClearances({a, b}, {});
  EXPECT_TRUE(d[0].deadlocked);
  EXPECT_EQ(d[0].cleared_up_to, -1);
  EXPECT_FALSE(d[1].deadlocked);
  // b waits for a to stand aside, not for a's job to end.
  ASSERT_FALSE(d[1].waits.empty());
  EXPECT_EQ(d[1].waits[0].blocker_robot_id, "a");
  EXPECT_EQ(d[1].waits[0].blocker_action, -1);
}

/// A route along `points` cut into legs of about `step_m`, as fleetnavd cuts actions into
/// segments.
ScheduledRoute Segmented(const std::string& robot, std::vector<Eigen::Vector2d> points,
                         double step_m, double t0) {
  std::vector<Eigen::Vector2d> fine{points.front()};
  for (size_t i = 1; i < points.size(); ++i) {
    const int n =
        std::max(1, static_cast<int>(std::round((points[i] - points[i - 1]).norm() / step_m)));
    for (int k = 1; k <= n; ++k) {
      fine.push_back(points[i - 1] + (points[i] - points[i - 1]) * (static_cast<double>(k) / n));
    }
  }
  return Route(robot, fine, t0);
}

TEST(TrafficScheduleTest, ARobotFollowsAnotherDownAnAisleOneRegionBehindIt) {
  // Both drive east along y = 0 in 2 m segments; a started first. b may enter a's way as soon
  // as a has left what b's first segment needs, not when a has left the whole aisle.
  ScheduledRoute a = Segmented("a", {{0, 0}, {20, 0}}, 2.0, 0.0);
  ScheduledRoute b = Segmented("b", {{-4, 0}, {16, 0}}, 2.0, 1.0);
  std::vector<TrafficClearanceDecision> d = DecideClearances({a, b}, {});
  EXPECT_EQ(d[0].cleared_up_to, 9);
  ASSERT_FALSE(d[1].waits.empty());
  EXPECT_EQ(d[1].waits[0].blocker_robot_id, "a");
  // b's second segment (-2 → 0 m) meets a's first (0 → 2 m), far from the end of the aisle
  // (a's segment 9).
  EXPECT_EQ(d[1].waits[0].action, 1);
  EXPECT_EQ(d[1].waits[0].blocker_action, 0);
  // a moves on: b follows, one region behind.
  a.first_unfinished = 5;
  a.cleared_up_to = 9;
  b.cleared_up_to = d[1].cleared_up_to;
  d = DecideClearances({a, b}, {});
  EXPECT_EQ(d[1].cleared_up_to, 5);  // up to 8 m, a's rear is beyond 9.5 m
  ASSERT_FALSE(d[1].waits.empty());
  EXPECT_EQ(d[1].waits[0].action, 6);
  EXPECT_EQ(d[1].waits[0].blocker_action, 5);  // the segment a is driving now
}

TEST(TrafficScheduleTest, ARobotThatHasArrivedStandsAtItsEndUntilItsJobEnds) {
  // a was cleared first down the way b follows and ends on it: once a has finished, b is not
  // cleared through where a now stands.
  ScheduledRoute a = Segmented("a", {{0, 0}, {10, 0}}, 2.0, 0.0);
  ScheduledRoute b = Segmented("b", {{-4, 0}, {16, 0}}, 2.0, 1.0);
  a.first_unfinished = 5;
  a.cleared_up_to = 4;
  b.first_unfinished = 2;
  b.cleared_up_to = 3;
  const std::vector<TrafficClearanceDecision> d = DecideClearances({a, b}, {});
  ASSERT_FALSE(d[1].waits.empty());
  EXPECT_EQ(d[1].waits[0].blocker_robot_id, "a");
  EXPECT_EQ(d[1].waits[0].blocker_action, -1);  // it stands there
  EXPECT_LT(d[1].cleared_up_to, 6);             // b's segment 6 ends at 10 m, on a
}

TEST(TrafficScheduleTest, ARobotStandingOnASegmentedActionHoldsTheWholeAction) {
  // a's one action, in five 2 m segments, ends past an idle robot at (9, 0): a does not drive
  // up to it (the idle robot may have to make way out past a), it waits at the action's start.
  ScheduledRoute a = Segmented("a", {{0, 0}, {10, 0}}, 2.0, 0.0);
  a.whole_from.assign(5, 0);
  std::vector<TrafficClearanceDecision> d =
      DecideClearances({a}, {ParkedRobot{"idle", At({9, 0})}});
  EXPECT_EQ(d[0].cleared_up_to, -1);
  ASSERT_FALSE(d[0].waits.empty());
  EXPECT_EQ(d[0].waits[0].action, 0);
  EXPECT_EQ(d[0].waits[0].blocker_robot_id, "idle");
  // Already cleared into the action (the robot stood still after): it keeps what it was
  // cleared for and is not cleared further.
  a.cleared_up_to = 1;
  d = DecideClearances({a}, {ParkedRobot{"idle", At({9, 0})}});
  EXPECT_EQ(d[0].cleared_up_to, 1);
  EXPECT_EQ(d[0].waits[0].action, 2);
}

TEST(TrafficScheduleTest, RobotsMeetingHeadOnInAnAisleStillPassItWhole) {
  // Opposite directions: b may not enter before a has left all of it.
  ScheduledRoute a = Segmented("a", {{0, 0}, {12, 0}, {12, 8}}, 2.0, 0.0);
  ScheduledRoute b = Segmented("b", {{14, -6}, {14, 0}, {-4, 0}}, 2.0, 1.0);
  std::vector<TrafficClearanceDecision> d = DecideClearances({a, b}, {});
  ASSERT_FALSE(d[1].waits.empty());
  EXPECT_EQ(d[1].waits[0].blocker_robot_id, "a");
  // a's last segment in the aisle ends at (12, 2) on its way north; b waits for it.
  EXPECT_GE(d[1].waits[0].blocker_action, 6);
}

/// Runs `routes` to their ends, one random robot moving on per step (a random delay for all
/// the others), deciding clearances before each step. Fails when two robots are ever in each
/// other's way (running action or standing place) or nobody can move; returns how often some
/// robot waited.
int RunWithRandomDelays(std::vector<ScheduledRoute> routes, std::mt19937& rng, int seed) {
  const int n = static_cast<int>(routes.size());
  int waited = 0;
  std::vector<bool> running(n, false);
  auto occupied = [&](int i) -> const CellSet& {
    const ScheduledRoute& r = routes[i];
    if (running[i]) return r.action_cells[r.first_unfinished];
    return r.first_unfinished == 0 ? r.start_cells : r.action_end_cells[r.first_unfinished - 1];
  };
  int idle_steps = 0;
  for (int step = 0; step < 20000; ++step) {
    std::vector<ScheduledRoute> active;
    std::vector<ParkedRobot> parked;
    std::vector<int> index;
    for (int i = 0; i < n; ++i) {
      if (routes[i].first_unfinished < static_cast<int>(routes[i].action_cells.size())) {
        active.push_back(routes[i]);
        index.push_back(i);
      } else {
        parked.push_back({routes[i].robot_id, routes[i].action_end_cells.back()});
      }
    }
    if (active.empty()) break;
    const std::vector<TrafficClearanceDecision> d = DecideClearances(active, parked);
    for (size_t j = 0; j < d.size(); ++j) {
      routes[index[j]].cleared_up_to = d[j].cleared_up_to;
      if (!d[j].waits.empty()) ++waited;
    }
    const int i = index[std::uniform_int_distribution<size_t>(0, index.size() - 1)(rng)];
    ScheduledRoute& r = routes[i];
    bool moved = false;
    if (running[i]) {
      running[i] = false;
      ++r.first_unfinished;
      moved = true;
    } else if (r.cleared_up_to >= r.first_unfinished) {
      running[i] = true;
      moved = true;
    }
    idle_steps = moved ? 0 : idle_steps + 1;
    if (idle_steps >= 400) {
      std::string state;
      for (size_t j = 0; j < d.size(); ++j) {
        absl::StrAppend(&state, "\n  ", d[j].robot_id, ": cleared to ", d[j].cleared_up_to,
                        d[j].deadlocked ? " (held)" : "");
        for (const TrafficWait& w : d[j].waits) {
          absl::StrAppend(&state, "; ", w.action, " waits for ", w.blocker_robot_id, " ",
                          w.blocker_action);
        }
      }
      ADD_FAILURE() << "seed " << seed << ": nobody can move (deadlock)" << state;
      return waited;
    }
    for (int x = 0; x < n; ++x) {
      for (int y = x + 1; y < n; ++y) {
        EXPECT_FALSE(occupied(x).Intersects(occupied(y)))
            << "seed " << seed << ": " << routes[x].robot_id << " and " << routes[y].robot_id
            << " meet";
        if (occupied(x).Intersects(occupied(y))) return waited;
      }
    }
  }
  for (const ScheduledRoute& r : routes) {
    EXPECT_EQ(r.first_unfinished, static_cast<int>(r.action_cells.size()))
        << "seed " << seed << " robot " << r.robot_id;
  }
  return waited;
}

/// Four random routes from the west edge (y = 0, 3, 6, 9) to the east edge in a random order,
/// through two random points each, in legs of about `step_m` (0: one leg between points).
std::vector<ScheduledRoute> RandomCrossingRoutes(std::mt19937& rng, double step_m) {
  std::uniform_real_distribution<double> mid(5.0, 15.0);
  std::vector<int> exits{0, 1, 2, 3};
  std::shuffle(exits.begin(), exits.end(), rng);
  std::vector<ScheduledRoute> routes;
  for (int i = 0; i < 4; ++i) {
    const std::string robot(1, static_cast<char>('a' + i));
    std::vector<Eigen::Vector2d> points{{0.0, 3.0 * i},
                                        {mid(rng), mid(rng) - 5.0},
                                        {mid(rng), mid(rng) - 5.0},
                                        {20.0, 3.0 * exits[i]}};
    routes.push_back(step_m > 0.0 ? Segmented(robot, points, step_m, 0.5 * i)
                                  : Route(robot, points, 0.5 * i));
  }
  return routes;
}

// Four robots on random crossing routes, executed with random delays over 50 seeds: no two
// robots are ever in each other's way (running action or standing place), and all finish.
TEST(TrafficScheduleTest, RandomDelaysNeverCollideOrDeadlock) {
  int waited = 0;
  for (int seed = 1; seed <= 50; ++seed) {
    std::mt19937 rng(seed);
    waited += RunWithRandomDelays(RandomCrossingRoutes(rng, 0.0), rng, seed);
  }
  EXPECT_GT(waited, 0);  // the routes did cross
}

// The same in segments of 1.5 m, where robots follow one another through shared places.
TEST(TrafficScheduleTest, RandomDelaysOnSegmentedRoutesNeverCollideOrDeadlock) {
  int waited = 0;
  for (int seed = 1; seed <= 50; ++seed) {
    std::mt19937 rng(seed);
    waited += RunWithRandomDelays(RandomCrossingRoutes(rng, 1.5), rng, seed);
  }
  EXPECT_GT(waited, 0);
}

// Robots driving one corridor both ways in segments, with random delays. The corridor runs from
// (0, 0) to (20, 0); at each end four streets fan out (8 m long, 40° apart) and robot i comes
// from its street at one end and leaves by its street at the other, east or west at random:
// no robot ends where another starts or passes (a well-formed site).
TEST(TrafficScheduleTest, RandomDelaysInACorridorDrivenBothWaysNeverCollideOrDeadlock) {
  int waited = 0;
  const auto street = [](bool east_end, int i) -> Eigen::Vector2d {
    const double fan = (-60.0 + 40.0 * i) * kPi / 180.0;
    const double angle = east_end ? fan : kPi - fan;
    return Eigen::Vector2d(east_end ? 20.0 : 0.0, 0.0) +
           8.0 * Eigen::Vector2d(std::cos(angle), std::sin(angle));
  };
  for (int seed = 1; seed <= 50; ++seed) {
    std::mt19937 rng(seed);
    std::vector<ScheduledRoute> routes;
    for (int i = 0; i < 4; ++i) {
      const bool east = rng() % 2 == 0;
      const Eigen::Vector2d west_end(0.0, 0.0);
      const Eigen::Vector2d east_end(20.0, 0.0);
      routes.push_back(Segmented(std::string(1, static_cast<char>('a' + i)),
                                 {street(!east, i), east ? west_end : east_end,
                                  east ? east_end : west_end, street(east, i)},
                                 1.5, 0.5 * i));
    }
    waited += RunWithRandomDelays(std::move(routes), rng, seed);
  }
  EXPECT_GT(waited, 0);
}

/// A planner that answers every request with the straight line and remembers the requests.
class StraightLinePlanner : public SingleRobotPlanner {
 public:
  absl::StatusOr<PathResult> Plan(const PathRequest& request, std::stop_token) override {
    requests.push_back(request);
    PathResult result;
    result.poses = {request.start, request.goal};
    result.length_m = (request.goal.translation() - request.start.translation()).norm();
    return result;
  }
  std::vector<PathRequest> requests;
};

TEST(RoutePredictionTest, AWaypointWithAYawIsReachedAtItAndOthersFaceTheNextPoint) {
  StraightLinePlanner planner;
  absl::StatusOr<WaypointPath> path = PlanThroughWaypoints(
      planner, Pose2(), Pose2(0, 0, 0), {{2, 0}, {2, 2}}, Pose2(4, 2, 0), 1.0, {std::nullopt, kPi});
  ASSERT_TRUE(path.ok()) << path.status();
  ASSERT_EQ(planner.requests.size(), 3u);
  EXPECT_NEAR(planner.requests[0].goal.yaw_rad(), (kPi / 2), 1e-12);  // faces (2, 2)
  EXPECT_NEAR(planner.requests[0].goal_tolerance_rad, 0.8, 1e-12);
  EXPECT_NEAR(planner.requests[1].goal.yaw_rad(), kPi, 1e-12);  // as the route says
  EXPECT_NEAR(planner.requests[1].goal_tolerance_rad, 0.1, 1e-12);
  // And the route's move action is predicted sideways with the heading held.
  fleetnav::Route route;
  route.actions.push_back({MoveAction{0.0, 1.5, 0.3}, {}});
  absl::StatusOr<std::vector<PredictedAction>> predicted =
      PredictRoute(route, Pose2(1, 1, (kPi / 2)), nullptr, nullptr, Pose2());
  ASSERT_TRUE(predicted.ok()) << predicted.status();
  EXPECT_TRUE(predicted->at(0).poses.back().IsNear(Pose2(-0.5, 1, (kPi / 2)), 1e-9, 1e-9));
  EXPECT_NEAR(predicted->at(0).duration_s, 5.0, 1e-9);

  // A trolley dock goes before the trolley's nearer end and under it to its centre.
  MarkerSet site;
  site.trolleys.push_back({"t1", Pose2(5, 0, 0), Eigen::Vector2d(1.0, 0.7), 0.02});
  fleetnav::Route dock;
  dock.actions.push_back({DockAction{DockTarget::kTrolley, "t1"}, {}});
  for (const double start_x : {0.0, 10.0}) {
    predicted = PredictRoute(dock, Pose2(start_x, 0, 0), &site, nullptr, Pose2());
    ASSERT_TRUE(predicted.ok()) << predicted.status();
    const std::vector<Pose2>& poses = predicted->at(0).poses;
    EXPECT_NEAR(poses.back().x_m(), 5.0, 1e-9);
    EXPECT_NEAR(poses.back().y_m(), 0.0, 1e-9);
    // Never past the centre on the far side: it came in from the start's end.
    for (const Pose2& p : poses) {
      EXPECT_LE(std::abs(p.x_m() - start_x), std::abs(5.0 - start_x) + 1e-9) << start_x;
    }
  }
}

TEST(RoutePredictionTest, LegsChainFromTheStartAlongStripesAndTurns) {
  MarkerSet markers;
  StripeMarker stripe;
  stripe.id = 10;
  stripe.position_m = {5.0, 2.0};
  stripe.yaw_rad = 0.0;
  stripe.length_m = 6.0;  // x 2..8 at y = 2
  stripe.kind = MarkerKind::kFollowStripe;
  stripe.stripe_id = 3;
  markers.markers.push_back(stripe);
  fleetnav::Route route;
  route.actions.push_back({StraightAction{2.0, 0.5}, {}});
  route.actions.push_back({TurnAction{kPi / 2, 0.5}, {}});
  route.actions.push_back({StraightAction{2.0, 0.5}, {}});
  route.actions.push_back({TurnAction{-kPi / 2, 0.5}, {}});
  route.actions.push_back({StripeNavigationAction{3, 0.0, 0.25}, {EndConditionKind::kStripeEnd}});
  absl::StatusOr<std::vector<PredictedAction>> predicted =
      PredictRoute(route, Pose2(0, 0, 0), &markers, nullptr, Pose2());
  ASSERT_TRUE(predicted.ok()) << predicted.status();
  ASSERT_EQ(predicted->size(), 5u);
  EXPECT_TRUE(predicted->at(0).poses.back().IsNear(Pose2(2, 0, 0), 1e-9, 1e-9));
  EXPECT_NEAR(predicted->at(0).duration_s, 4.0, 1e-9);
  EXPECT_NEAR(predicted->at(1).duration_s, kPi, 1e-9);
  EXPECT_TRUE(predicted->at(2).poses.back().IsNear(Pose2(2, 2, kPi / 2), 1e-9, 1e-9));
  EXPECT_TRUE(predicted->at(4).poses.back().IsNear(Pose2(8, 2, 0), 1e-9, 1e-9));
  EXPECT_NEAR(predicted->at(4).duration_s, 6.0 / 0.25, 1e-6);
  for (const PredictedAction& action : *predicted) {
    for (size_t i = 1; i < action.poses.size(); ++i) {
      EXPECT_LE((action.poses[i].translation() - action.poses[i - 1].translation()).norm(),
                0.1 + 1e-9);
    }
  }
  route.actions.back().params = StripeNavigationAction{4, 0.0, 0.25};
  EXPECT_EQ(PredictRoute(route, Pose2(0, 0, 0), &markers, nullptr, Pose2()).status().code(),
            absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fleetnav::planner

namespace fleetnav::planner {
namespace {

bool SameDecisions(const std::vector<TrafficClearanceDecision>& a,
                   const std::vector<TrafficClearanceDecision>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i].robot_id != b[i].robot_id || a[i].cleared_up_to != b[i].cleared_up_to ||
        a[i].deadlocked != b[i].deadlocked || a[i].waits.size() != b[i].waits.size()) {
      return false;
    }
    for (size_t w = 0; w < a[i].waits.size(); ++w) {
      const TrafficWait& x = a[i].waits[w];
      const TrafficWait& y = b[i].waits[w];
      if (x.robot_id != y.robot_id || x.action != y.action ||
          x.blocker_robot_id != y.blocker_robot_id || x.blocker_action != y.blocker_action) {
        return false;
      }
    }
  }
  return true;
}

// Six robots on random crossing routes, executed with random delays, re-predicted now and then
// and finishing at random: the decider's remembered blocks give the same decisions as
// computing them afresh at every step, over 30 seeds.
TEST(ClearanceDeciderTest, RememberingSharedPlacesChangesNoDecision) {
  size_t most_remembered = 0;
  int waits_seen = 0;
  for (int seed = 1; seed <= 30; ++seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> mid(5.0, 15.0);
    std::vector<ScheduledRoute> routes;
    uint64_t next_id = 1;
    for (int i = 0; i < 6; ++i) {
      routes.push_back(Route(std::string(1, static_cast<char>('a' + i)),
                             {{0.0, 2.0 * i},
                              {mid(rng), mid(rng) - 5.0},
                              {mid(rng), mid(rng) - 5.0},
                              {mid(rng), mid(rng) - 5.0},
                              {20.0, 2.0 * i}},
                             0.5 * i));
      routes.back().cells_id = next_id++;
    }
    ClearanceDecider decider;
    std::vector<bool> running(routes.size(), false);
    for (int step = 0; step < 400; ++step) {
      std::vector<const ScheduledRoute*> active;
      std::vector<ScheduledRoute*> active_mutable;
      std::vector<ParkedRobot> parked;
      for (ScheduledRoute& r : routes) {
        if (r.first_unfinished < 4) {
          active.push_back(&r);
          active_mutable.push_back(&r);
        } else {
          parked.push_back({r.robot_id, r.action_end_cells.back()});
        }
      }
      if (active.empty()) break;
      const std::vector<TrafficClearanceDecision> fresh = DecideClearances(active, parked);
      const std::vector<TrafficClearanceDecision> remembered = decider.Decide(active, parked);
      ASSERT_TRUE(SameDecisions(fresh, remembered)) << "seed " << seed << " step " << step;
      ASSERT_LE(decider.remembered_pairs(), active.size() * (active.size() - 1) / 2);
      most_remembered = std::max(most_remembered, decider.remembered_pairs());
      for (size_t j = 0; j < fresh.size(); ++j) {
        active_mutable[j]->cleared_up_to = fresh[j].cleared_up_to;
        waits_seen += fresh[j].waits.empty() ? 0 : 1;
      }
      // One robot moves on; now and then another's cells are predicted again (a new id).
      const size_t j = std::uniform_int_distribution<size_t>(0, active.size() - 1)(rng);
      ScheduledRoute& r = *active_mutable[j];
      const size_t i = static_cast<size_t>(&r - routes.data());
      if (running[i]) {
        running[i] = false;
        ++r.first_unfinished;
      } else if (r.cleared_up_to >= r.first_unfinished) {
        running[i] = true;
      }
      if (std::uniform_int_distribution<int>(0, 9)(rng) == 0) {
        active_mutable[std::uniform_int_distribution<size_t>(0, active.size() - 1)(rng)]->cells_id =
            next_id++;
      }
    }
  }
  EXPECT_GT(most_remembered, 0u);
  EXPECT_GT(waits_seen, 0);
}

}  // namespace
}  // namespace fleetnav::planner
