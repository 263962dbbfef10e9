#include "fleetnav/scenario/zone_truth.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace fleetnav::scenario {
namespace {

ZoneSet Zones() {
  ZoneSet zones;
  zones.zones.push_back({"pen", ZoneKind::kNoGo, {{4, -1}, {5, -1}, {5, 1}, {4, 1}}, 0.0, 1});
  zones.zones.push_back(
      {"slow", ZoneKind::kSpeedLimit, {{0, -1}, {2, -1}, {2, 1}, {0, 1}}, 0.3, 1});
  return zones;
}

// A robot driving along y = `y_m` from x = 0 at `speed_mps`, sampled at 10 Hz for `end_s`.
std::vector<TruthSample> Drive(double y_m, double speed_mps, double end_s, double yaw_rad = 0.0) {
  std::vector<TruthSample> out;
  for (int i = 0; i * 0.1 <= end_s + 1e-9; ++i)
    out.push_back({i * 0.1, speed_mps * i * 0.1, y_m, yaw_rad});
  return out;
}

const Polygon2 kBox = {{-0.3, -0.2}, {0.3, -0.2}, {0.3, 0.2}, {-0.3, 0.2}};

TEST(ZoneTruthTest, AFootprintThatReachesANoGoZoneIsOneEntryAndTheFirstIsNamed) {
  // Straight through the pen: one entry however many samples it stays in.
  const ZoneTruth through =
      JudgeZones(Zones(), {{"omni1", Drive(0.0, 1.0, 8.0)}}, {{"omni1", kBox}});
  EXPECT_EQ(through.no_go_entries, 1);
  EXPECT_THAT(through.first_no_go_entry, ::testing::HasSubstr("omni1 entered no-go zone 'pen'"));
  // Along y = 1.25, 0.25 m beside the pen's edge: the 0.2 m half-width keeps it out.
  EXPECT_EQ(
      JudgeZones(Zones(), {{"omni1", Drive(1.25, 1.0, 8.0, 0.0)}}, {{"omni1", kBox}}).no_go_entries,
      0);
  // Turned across (yaw 90°) its 0.3 m half-length reaches in, the centre does not.
  EXPECT_EQ(JudgeZones(Zones(), {{"omni1", Drive(1.25, 1.0, 8.0, M_PI / 2)}}, {{"omni1", kBox}})
                .no_go_entries,
            1);
  EXPECT_EQ(JudgeZones(Zones(), {{"omni1", Drive(1.35, 1.0, 8.0, M_PI / 2)}}, {{"omni1", kBox}})
                .no_go_entries,
            0);
}

TEST(ZoneTruthTest, TheSpeedInAZoneIsMeasuredWhileTheCentreIsInIt) {
  // 0.25 m/s through the slow zone, then 1 m/s after it.
  std::vector<TruthSample> samples = Drive(0.0, 0.25, 8.0);
  const double x_end = samples.back().x_m;
  for (int i = 1; i <= 20; ++i) samples.push_back({8.0 + i * 0.1, x_end + i * 0.1, 0.0, 0.0});
  const ZoneTruth truth = JudgeZones(Zones(), {{"lely1", samples}}, {});
  EXPECT_NEAR(truth.max_speed_in_zone_mps.at("slow"), 0.25, 1e-9);
  EXPECT_EQ(truth.max_speed_in_zone_mps.count("pen"), 0u);
  const ZoneTruth fast = JudgeZones(Zones(), {{"lely1", Drive(0.0, 0.8, 3.0)}}, {});
  EXPECT_NEAR(fast.max_speed_in_zone_mps.at("slow"), 0.8, 1e-9);
}

TEST(ZoneTruthTest, RobotsInAOneAtATimeZoneAreCountedAndAnEntryIntoAFullOneIsNamed) {
  // A door 1 m wide from x = 4 to 5; robots drive east at 1 m/s along y = 0, each with a
  // 0.6 m long box: one is in the door (footprint overlapping) for 1.6 s.
  ZoneSet door;
  door.zones.push_back({"door", ZoneKind::kOneAtATime, {{4, -1}, {5, -1}, {5, 1}, {4, 1}}, 0.0, 1});
  const auto shifted = [](double start_s) {
    std::vector<TruthSample> samples = Drive(0.0, 1.0, 10.0);
    for (TruthSample& s : samples) s.x_m -= start_s;  // at x = 0 start_s later
    return samples;
  };
  const std::map<std::string, Polygon2> boxes{{"a", kBox}, {"b", kBox}, {"c", kBox}};
  // 2 s apart: the first has left before the second comes.
  const ZoneTruth apart = JudgeZones(door, {{"a", shifted(0.0)}, {"b", shifted(2.0)}}, boxes);
  EXPECT_EQ(apart.max_robots_in_zone.at("door"), 1);
  EXPECT_EQ(apart.over_capacity_entries, 0);
  EXPECT_TRUE(apart.first_over_capacity.empty());
  // 1 s apart: the second enters while the first is still in it.
  const ZoneTruth close = JudgeZones(door, {{"a", shifted(0.0)}, {"b", shifted(1.0)}}, boxes);
  EXPECT_EQ(close.max_robots_in_zone.at("door"), 2);
  EXPECT_EQ(close.over_capacity_entries, 1);
  EXPECT_THAT(close.first_over_capacity,
              ::testing::HasSubstr("b entered one-at-a-time zone 'door' (admits 1)"));
  // A door for two: three close together are one entry too many.
  door.zones[0].capacity = 2;
  const ZoneTruth three =
      JudgeZones(door, {{"a", shifted(0.0)}, {"b", shifted(0.5)}, {"c", shifted(1.0)}}, boxes);
  EXPECT_EQ(three.max_robots_in_zone.at("door"), 3);
  EXPECT_EQ(three.over_capacity_entries, 1);
  EXPECT_THAT(three.first_over_capacity, ::testing::HasSubstr("c entered"));
}

TEST(ZoneTruthTest, ZonesPutDuringARunAreJudgedFromTheirTimeOn) {
  // Through the pen (x from 4 to 5) at 1 m/s from x = 0: the box overlaps it from 3.7 s to 5.3 s.
  const std::map<std::string, std::vector<TruthSample>> truth{{"omni1", Drive(0.0, 1.0, 8.0)}};
  const std::map<std::string, Polygon2> boxes{{"omni1", kBox}};
  const ZoneSet none;
  // Put once the robot has passed it: no entry.
  EXPECT_EQ(JudgeZonesOverTime({{0.0, none}, {6.0, Zones()}}, truth, boxes).no_go_entries, 0);
  // Put while the robot is in it: an entry, named.
  const ZoneTruth on_it = JudgeZonesOverTime({{0.0, none}, {5.0, Zones()}}, truth, boxes);
  EXPECT_EQ(on_it.no_go_entries, 1);
  EXPECT_THAT(on_it.first_no_go_entry, ::testing::HasSubstr("at 5.00 s"));
  // Lifted before the robot came: no entry; the speed in the slow zone (passed before 2.3 s)
  // is still measured while that version was in force.
  const ZoneTruth lifted = JudgeZonesOverTime({{0.0, Zones()}, {3.0, none}}, truth, boxes);
  EXPECT_EQ(lifted.no_go_entries, 0);
  EXPECT_NEAR(lifted.max_speed_in_zone_mps.at("slow"), 1.0, 1e-9);
  // In force all along: as JudgeZones.
  EXPECT_EQ(JudgeZonesOverTime({{0.0, Zones()}}, truth, boxes).no_go_entries, 1);
}

TEST(ZoneTruthTest, AStoppedRobotThatMovesAndOneThatEntersAStoppedZoneAreCounted) {
  // Robot "in" stands in the slow zone; robot "out" drives east along y = 0.5 from x = -6 at
  // 0.5 m/s, through the zone from 12 s.
  std::vector<TruthSample> in;
  for (int i = 0; i <= 300; ++i) in.push_back({i * 0.1, 1.0, 0.0, 0.0});
  std::vector<TruthSample> out;
  for (int i = 0; i <= 300; ++i) out.push_back({i * 0.1, -6.0 + 0.05 * i, 0.5, 0.0});
  const Polygon2 slow = Zones().zones[1].polygon_in_map;
  StopWindow zone_stop{5.0, 25.0, "slow", slow};
  const StopTruth judged = JudgeStops({zone_stop}, {{"in", in}, {"out", out}}, {});
  EXPECT_DOUBLE_EQ(judged.max_motion_while_stopped_m, 0.0);
  EXPECT_EQ(judged.stopped_zone_entries, 1);  // "out" reached x = 0 at 12 s
  // A whole-fleet stop applies to both: "out" moved.
  const StopTruth fleet = JudgeStops({{5.0, 25.0, "", {}}}, {{"in", in}, {"out", out}}, {});
  EXPECT_NEAR(fleet.max_motion_while_stopped_m, 0.05 * (250 - 70), 1e-6);
  EXPECT_THAT(fleet.worst, ::testing::HasSubstr("out moved"));
  // Creeping 1 cm a second in the stopped zone shows as its distance.
  for (int i = 0; i <= 300; ++i) in[i].x_m = 1.0 + 0.001 * i;
  EXPECT_NEAR(JudgeStops({zone_stop}, {{"in", in}}, {}).max_motion_while_stopped_m,
              0.001 * (250 - 70), 1e-9);
}

}  // namespace
}  // namespace fleetnav::scenario
