#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "fleetnav/scenario/scenario.hpp"

namespace fleetnav::scenario {
namespace {

using ::testing::HasSubstr;

/// A scenario on the supermarket world, with a zone file `put.zones.yaml` beside it (a zone
/// named `aisle`) for its put_zones faults, and `faults` as written.
absl::StatusOr<Scenario> LoadWithFaults(const std::string& name, const std::string& faults) {
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / name;
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "put.zones.yaml") << "map: supermarket\n"
                                           "zones:\n"
                                           "  - {name: aisle, kind: speed_limit, speed_limit: 0.5,"
                                           " polygon: [[0, 0], [2, 0], [2, 1], [0, 1]]}\n";
  std::ofstream(dir / "s.yaml") << "world: " FLEETNAV_WORLDS_DIR
                                   "/supermarket.yaml\n"
                                   "jobs: [{id: go, goal: [3.0, -2.0, 90], robot: omni1}]\n"
                                << "faults:\n"
                                << faults;
  return LoadScenario((dir / "s.yaml").string());
}

TEST(ScenarioLoadTest, AStopMayNameAZonePutBeforeItAndZonesInForceAreTheLastPut) {
  absl::StatusOr<Scenario> s =
      LoadWithFaults("put-then-stop",
                     "  - {type: put_zones, at_s: 5, file: put.zones.yaml}\n"
                     "  - {type: stop_zone, zone: aisle, at_s: 5}\n"
                     "  - {type: stop_zone, zone: aisle, at_s: 9}\n");
  ASSERT_TRUE(s.ok()) << s.status();
  ASSERT_NE(ZonesInForceAt(*s, 1), nullptr);
  EXPECT_NE(ZonesInForceAt(*s, 2)->Find("aisle"), nullptr);
  // Before any put and without the scenario's own zones: none.
  EXPECT_EQ(ZonesInForceAt(*s, 0), nullptr);
}

TEST(ScenarioLoadTest, AStopOfAZoneNotYetPutOrUnknownIsRefusedNamingTheFault) {
  absl::StatusOr<Scenario> early =
      LoadWithFaults("stop-before-put",
                     "  - {type: stop_zone, zone: aisle, at_s: 4}\n"
                     "  - {type: put_zones, at_s: 5, file: put.zones.yaml}\n");
  ASSERT_TRUE(absl::IsInvalidArgument(early.status())) << early.status();
  EXPECT_THAT(early.status().message(),
              HasSubstr("faults[0].zone: 'aisle' is not a zone in force at 4 s"));
  // At the same time, the stop listed first is injected first.
  absl::StatusOr<Scenario> same_time =
      LoadWithFaults("stop-listed-first",
                     "  - {type: stop_zone, zone: aisle, at_s: 5}\n"
                     "  - {type: put_zones, at_s: 5, file: put.zones.yaml}\n");
  EXPECT_TRUE(absl::IsInvalidArgument(same_time.status())) << same_time.status();
  absl::StatusOr<Scenario> unknown =
      LoadWithFaults("stop-unknown",
                     "  - {type: put_zones, at_s: 5, file: put.zones.yaml}\n"
                     "  - {type: stop_zone, zone: bakery, at_s: 6}\n");
  ASSERT_TRUE(absl::IsInvalidArgument(unknown.status())) << unknown.status();
  EXPECT_THAT(unknown.status().message(), HasSubstr("faults[1].zone: 'bakery'"));
}

}  // namespace
}  // namespace fleetnav::scenario
