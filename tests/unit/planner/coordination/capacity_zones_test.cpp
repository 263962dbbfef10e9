#include "fleetnav/planner/coordination/capacity_zones.hpp"

#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "coordination/square_routes.hpp"

namespace fleetnav::planner {
namespace {

constexpr double kCellM = 0.25;  // as square_routes.hpp sweeps
using testing::Line;
using testing::Route;

/// A door 2 m wide (x) and 6 m deep (y) about the origin, admitting `capacity` robots.
ZoneSet Door(int capacity) {
  ZoneSet zones;
  zones.map_id = "m";
  zones.zones.push_back(
      {"door", ZoneKind::kOneAtATime, {{-1, -3}, {1, -3}, {1, 3}, {-1, 3}}, 0.0, capacity});
  // Zones of other kinds are not traffic coordination's.
  zones.zones.push_back(
      {"slow", ZoneKind::kSpeedLimit, {{3, -2}, {5, -2}, {5, 2}, {3, 2}}, 0.2, 1});
  return zones;
}

/// East along y = +2 and, starting 5 s later, west along y = -2: 4 m apart, never sharing floor,
/// both through the door.
std::vector<ScheduledRoute> Crossing() {
  return {Route("a", {{-6, 2}, {-4, 2}, {-2, 2}, {0, 2}, {2, 2}, {4, 2}, {6, 2}}, 0.0),
          Route("b", {{6, -2}, {4, -2}, {2, -2}, {0, -2}, {-2, -2}, {-4, -2}, {-6, -2}}, 5.0)};
}

TEST(CapacityZonesTest, AZoneForOneIsItsOwnCellsAndAZoneForMoreHasTokensNoFloorMeets) {
  const CapacityZones one = CapacityZones::Of(Door(1), kCellM);
  ASSERT_EQ(one.size(), 1u);  // the speed-limit zone is left out
  EXPECT_EQ(one.name(0), "door");
  EXPECT_EQ(one.capacity(0), 1);
  // Two routes through the door that never share floor both hold all of it there.
  std::vector<ScheduledRoute> routes = Crossing();
  std::map<std::string, int> lanes_a, lanes_b;
  one.Apply(routes[0], lanes_a, [](size_t) { return 0; });
  one.Apply(routes[1], lanes_b, [](size_t) { return 0; });
  EXPECT_TRUE(routes[0].action_cells[2].Intersects(routes[1].action_cells[3]));
  EXPECT_FALSE(Crossing()[0].action_cells[2].Intersects(Crossing()[1].action_cells[3]));
  // For three: three tokens, apart from each other and from any floor.
  const CapacityZones three = CapacityZones::Of(Door(3), kCellM);
  EXPECT_EQ(three.capacity(0), 3);
  std::vector<CellSet> laned;
  for (int lane = 0; lane < 3; ++lane) {
    std::map<std::string, int> lanes{{"door", lane}};
    ScheduledRoute r = Crossing()[0];
    three.Apply(r, lanes, [](size_t) { return 0; });
    EXPECT_EQ(r.action_cells[2].size(), Crossing()[0].action_cells[2].size() + 1);
    laned.push_back(r.action_cells[2]);
  }
  const CellSet elsewhere = Line({0, -2}, {0, -2});  // floor in the door, off route a
  for (int lane = 0; lane < 3; ++lane) {
    EXPECT_FALSE(laned[lane].Intersects(elsewhere));
    for (int other = 0; other < lane; ++other) {
      // Each holds route a's own floor, so they meet there; a token alone meets only itself.
      EXPECT_TRUE(laned[lane].Intersects(laned[other]));
    }
  }
  const CellSet token = CellSet::OfCell(kLaneTokenCell, kLaneTokenCell + 1);
  EXPECT_TRUE(laned[1].Intersects(token));
  EXPECT_FALSE(laned[0].Intersects(token));
  EXPECT_FALSE(laned[2].Intersects(token));
}

TEST(CapacityZonesTest, ARouteMeetingTheZoneHoldsItsLaneOnlyWhereItMeetsIt) {
  const CapacityZones zones = CapacityZones::Of(Door(1), kCellM);
  std::vector<ScheduledRoute> routes = Crossing();
  ScheduledRoute before = routes[0];
  std::map<std::string, int> lanes;
  int chosen = 0;
  zones.Apply(routes[0], lanes, [&](size_t) {
    ++chosen;
    return 0;
  });
  EXPECT_EQ(chosen, 1);  // once per zone, then kept
  EXPECT_EQ(lanes.at("door"), 0);
  // Legs 2 (to x = 0) and 3 (from x = 0) meet the door; the others are as they were.
  for (size_t k = 0; k < before.action_cells.size(); ++k) {
    const bool meets = k == 2 || k == 3;
    EXPECT_EQ(routes[0].action_cells[k].size() > before.action_cells[k].size(), meets) << k;
  }
  EXPECT_EQ(routes[0].start_cells.size(), before.start_cells.size());
  // Predicted again, it keeps its lane without choosing.
  zones.Apply(before, lanes, [&](size_t) {
    ++chosen;
    return 0;
  });
  EXPECT_EQ(chosen, 1);
}

TEST(CapacityZonesTest, AOneRobotZoneLetsTheSecondRobotInOnlyAfterTheFirstHasLeftIt) {
  std::vector<ScheduledRoute> routes = Crossing();
  // Alone, the two routes never meet: both are cleared to their ends.
  for (const TrafficClearanceDecision& d : DecideClearances(routes, {})) {
    EXPECT_EQ(d.cleared_up_to, 5) << d.robot_id;
  }
  const CapacityZones zones = CapacityZones::Of(Door(1), kCellM);
  std::map<std::string, int> lanes_a, lanes_b;
  zones.Apply(routes[0], lanes_a, [](size_t) { return 0; });
  zones.Apply(routes[1], lanes_b, [](size_t) { return 0; });
  std::vector<TrafficClearanceDecision> decisions = DecideClearances(routes, {});
  EXPECT_EQ(decisions[0].cleared_up_to, 5);  // a, expected first, goes through
  // b waits outside, at the end of its last leg before the door, for a's last leg in it.
  EXPECT_EQ(decisions[1].cleared_up_to, 1);
  ASSERT_EQ(decisions[1].waits.size(), 1u);
  EXPECT_EQ(decisions[1].waits[0].blocker_robot_id, "a");
  EXPECT_EQ(decisions[1].waits[0].blocker_action, 3);
  EXPECT_TRUE(zones.Meeting(Crossing()[1].action_end_cells[1]).empty());
  // Once a has finished leg 3, b goes in.
  routes[0].first_unfinished = 4;
  routes[0].cleared_up_to = 5;
  decisions = DecideClearances(routes, {});
  EXPECT_EQ(decisions[1].cleared_up_to, 5);
}

TEST(CapacityZonesTest, ATwoRobotZoneGivesTwoRoutesTwoLanesAndLetsBothIn) {
  std::vector<ScheduledRoute> routes = Crossing();
  const CapacityZones zones = CapacityZones::Of(Door(2), kCellM);
  std::map<std::string, int> lanes_a, lanes_b;
  std::vector<int> in_use;
  zones.Apply(routes[0], lanes_a,
              [&](size_t z) { return LeastUsedLane(zones.capacity(z), in_use); });
  in_use.push_back(lanes_a.at("door"));
  zones.Apply(routes[1], lanes_b,
              [&](size_t z) { return LeastUsedLane(zones.capacity(z), in_use); });
  EXPECT_NE(lanes_a.at("door"), lanes_b.at("door"));
  for (const TrafficClearanceDecision& d : DecideClearances(routes, {})) {
    EXPECT_EQ(d.cleared_up_to, 5) << d.robot_id;
  }
  // A third route, in b's lane, waits outside for b (expected first) to leave the door.
  ScheduledRoute c = Route("c", {{-6, 0}, {-4, 0}, {-2, 0}, {0, 0}, {2, 0}}, 8.0);
  std::map<std::string, int> lanes_c{{"door", lanes_b.at("door")}};
  zones.Apply(c, lanes_c, [](size_t) { return 0; });
  routes.push_back(c);
  const std::vector<TrafficClearanceDecision> three = DecideClearances(routes, {});
  EXPECT_EQ(three[0].cleared_up_to, 5);
  EXPECT_EQ(three[1].cleared_up_to, 5);
  EXPECT_EQ(three[2].cleared_up_to, 1);
  ASSERT_FALSE(three[2].waits.empty());
  EXPECT_EQ(three[2].waits[0].blocker_robot_id, "b");
}

TEST(CapacityZonesTest, ARobotStandingInTheZoneHoldsItsLane) {
  const CapacityZones zones = CapacityZones::Of(Door(1), kCellM);
  const CellSet inside = Line({0, 1.5}, {0, 1.5});
  const CellSet outside = Line({-4, 1}, {-4, 1});
  EXPECT_GT(zones.Standing(inside, [](size_t) { return 0; }).size(), inside.size() * 4);
  EXPECT_EQ(zones.Standing(outside, [](size_t) { return 0; }).size(), outside.size());
  // A route through the door is not cleared into it past a robot standing there.
  std::vector<ScheduledRoute> routes = {Crossing()[1]};
  std::map<std::string, int> lanes;
  zones.Apply(routes[0], lanes, [](size_t) { return 0; });
  const std::vector<TrafficClearanceDecision> decisions = DecideClearances(
      routes,
      {ParkedRobot{"p", zones.Standing(Line({0.5, 1.5}, {0.5, 1.5}), [](size_t) { return 0; })}});
  EXPECT_EQ(decisions[0].cleared_up_to, 1);
}

TEST(CapacityZonesTest, TheLeastUsedLaneIsTheLowestOfThoseTied) {
  EXPECT_EQ(LeastUsedLane(1, {0, 0, 0}), 0);
  EXPECT_EQ(LeastUsedLane(3, {0, 2}), 1);
  EXPECT_EQ(LeastUsedLane(3, {}), 0);
  EXPECT_EQ(LeastUsedLane(2, {0, 7, -1}), 1);
}

}  // namespace
}  // namespace fleetnav::planner
