#include "fleetnav/planner/grid/movingai.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "test_maps.hpp"

namespace fleetnav::planner {
namespace {

using ::testing::HasSubstr;

TEST(MovingAiMapTest, ParsesCellsAndPassability) {
  absl::StatusOr<MovingAiMap> map =
      ParseMovingAiMap("type octile\nheight 2\nwidth 3\nmap\n.@T\r\nGS.\n");
  ASSERT_TRUE(map.ok()) << map.status();
  EXPECT_EQ(map->width, 3);
  EXPECT_EQ(map->height, 2);
  EXPECT_TRUE(map->Passable(0, 0));
  EXPECT_FALSE(map->Passable(1, 0));
  EXPECT_FALSE(map->Passable(2, 0));
  EXPECT_TRUE(map->Passable(0, 1));
  EXPECT_TRUE(map->Passable(1, 1));
  EXPECT_FALSE(map->Passable(3, 1));
  EXPECT_FALSE(map->Passable(-1, 0));
}

struct MalformedCase {
  const char* text;
  const char* expected_line;
};

class MalformedMapTest : public ::testing::TestWithParam<MalformedCase> {};

TEST_P(MalformedMapTest, IsInvalidArgumentNamingTheLine) {
  absl::StatusOr<MovingAiMap> map = ParseMovingAiMap(GetParam().text);
  ASSERT_FALSE(map.ok());
  EXPECT_EQ(map.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(map.status().message()), HasSubstr(GetParam().expected_line));
}

INSTANTIATE_TEST_SUITE_P(
    Cases, MalformedMapTest,
    ::testing::Values(MalformedCase{"", "line 1"},
                      MalformedCase{"kind octile\nheight 1\nwidth 1\nmap\n.\n", "line 1"},
                      MalformedCase{"type octile\nheight x\nwidth 1\nmap\n.\n", "line 2"},
                      MalformedCase{"type octile\nheight 1\nwidth -3\nmap\n.\n", "line 3"},
                      MalformedCase{"type octile\nheight 1\nwidth 1\nmop\n.\n", "line 4"},
                      MalformedCase{"type octile\nheight 2\nwidth 2\nmap\n..\n.\n", "line 6"},
                      MalformedCase{"type octile\nheight 2\nwidth 2\nmap\n..\n", "line 6"},
                      MalformedCase{"type octile\nheight 1\nwidth 2\nmap\n.x\n", "line 5"},
                      MalformedCase{"type octile\nheight 1\nwidth 1\nmap\n.\n.\n", "line 6"}));

TEST(MovingAiScenarioTest, ParsesEntries) {
  absl::StatusOr<std::vector<ScenarioEntry>> entries = ParseMovingAiScenario(
      "version 1\n3\tm.map\t32\t32\t5\t16\t31\t24\t31.31370850\n0\tm.map\t32\t32\t1\t2\t3\t4\t2\n");
  ASSERT_TRUE(entries.ok()) << entries.status();
  ASSERT_EQ(entries->size(), 2u);
  EXPECT_EQ((*entries)[0].bucket, 3);
  EXPECT_EQ((*entries)[0].map_name, "m.map");
  EXPECT_EQ((*entries)[0].start_x, 5);
  EXPECT_EQ((*entries)[0].start_y, 16);
  EXPECT_EQ((*entries)[0].goal_x, 31);
  EXPECT_EQ((*entries)[0].goal_y, 24);
  EXPECT_NEAR((*entries)[0].optimal_length, 31.3137085, 1e-9);
  EXPECT_EQ((*entries)[1].goal_y, 4);
}

class MalformedScenarioTest : public ::testing::TestWithParam<MalformedCase> {};

TEST_P(MalformedScenarioTest, IsInvalidArgumentNamingTheLine) {
  absl::StatusOr<std::vector<ScenarioEntry>> entries = ParseMovingAiScenario(GetParam().text);
  ASSERT_FALSE(entries.ok());
  EXPECT_EQ(entries.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(entries.status().message()), HasSubstr(GetParam().expected_line));
}

INSTANTIATE_TEST_SUITE_P(
    Cases, MalformedScenarioTest,
    ::testing::Values(MalformedCase{"0\tm\t1\t1\t0\t0\t0\t0\t0\n", "line 1"},
                      MalformedCase{"version 1\n0\tm\t4\t4\t0\t0\t1\t1\n", "line 2"},
                      MalformedCase{
                          "version 1\n0\tm\t4\t4\t0\t0\t1\t1\t1\n0\tm\t4\t4\ta\t0\t1\t1\t1\n",
                          "line 3"},
                      MalformedCase{"version 1\n0\tm\t4\t4\t0\t0\t9\t1\t1\n", "line 2"},
                      MalformedCase{"version 1\n0\tm\t4\t4\t0\t0\t1\t1\tfast\n", "line 2"}));

TEST(MovingAiFilesTest, MissingFileIsNotFound) {
  EXPECT_EQ(LoadMovingAiMap("/nonexistent/x.map").status().code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(LoadMovingAiScenario("/nonexistent/x.scen").status().code(),
            absl::StatusCode::kNotFound);
}

TEST(MovingAiFilesTest, LoadsGeneratedMapAndScenarioFilesOfEachBenchmarkFamily) {
  struct Family {
    std::string name;
    std::vector<std::string> rows;
  };
  const std::vector<Family> families = {
      {"random-32-32-20", fleetnav::testing::RandomMapRows(32, 32, 20, 7)},
      {"warehouse-4-3-10-2", fleetnav::testing::WarehouseMapRows(4, 3, 10, 2)},
      {"room-4-4-8", fleetnav::testing::RoomsMapRows(4, 4, 8, 7)},
  };
  const std::string dir = ::testing::TempDir();
  for (const Family& family : families) {
    SCOPED_TRACE(family.name);
    const std::string map_path = dir + "/" + family.name + ".map";
    const std::string scen_path = dir + "/" + family.name + ".scen";
    ASSERT_TRUE(fleetnav::testing::WriteTextFile(map_path,
                                                 fleetnav::testing::MovingAiMapText(family.rows)));
    ASSERT_TRUE(fleetnav::testing::WriteTextFile(
        scen_path, fleetnav::testing::ScenarioText(family.rows, family.name + ".map", 100, 3)));
    absl::StatusOr<MovingAiMap> map = LoadMovingAiMap(map_path);
    ASSERT_TRUE(map.ok()) << map.status();
    EXPECT_EQ(map->width, static_cast<int>(family.rows.front().size()));
    EXPECT_EQ(map->height, static_cast<int>(family.rows.size()));
    int blocked = 0;
    for (bool p : map->passable) blocked += p ? 0 : 1;
    EXPECT_GT(blocked, 0);
    absl::StatusOr<std::vector<ScenarioEntry>> scen = LoadMovingAiScenario(scen_path);
    ASSERT_TRUE(scen.ok()) << scen.status();
    ASSERT_EQ(scen->size(), 100u);
    for (const ScenarioEntry& e : *scen) {
      EXPECT_EQ(e.map_name, family.name + ".map");
      EXPECT_TRUE(map->Passable(e.start_x, e.start_y));
      EXPECT_TRUE(map->Passable(e.goal_x, e.goal_y));
      // The generated maps are connected, so every goal has a finite distance.
      EXPECT_GE(e.optimal_length, std::abs(e.goal_x - e.start_x) + std::abs(e.goal_y - e.start_y));
    }
  }
}

}  // namespace
}  // namespace fleetnav::planner
