// fleetnav-scenario sweep's pure parts: the seed list and the summary of finished runs.
#include "fleetnav/scenario/sweep.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sstream>

namespace fleetnav::scenario {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

TEST(ParseSeedsTest, RangesListsAndSingleSeeds) {
  EXPECT_THAT(ParseSeeds("1-4").value(), ElementsAre(1u, 2u, 3u, 4u));
  EXPECT_THAT(ParseSeeds("7").value(), ElementsAre(7u));
  EXPECT_THAT(ParseSeeds("1-2,9,20-21").value(), ElementsAre(1u, 2u, 9u, 20u, 21u));
  EXPECT_EQ(ParseSeeds("1-100").value().size(), 100u);
}

TEST(ParseSeedsTest, WhatIsNoSeedIsNamed) {
  EXPECT_THAT(ParseSeeds("5-1").status().message(), HasSubstr("'5-1' runs backwards"));
  EXPECT_THAT(ParseSeeds("1,x").status().message(), HasSubstr("'x' is neither"));
  EXPECT_THAT(ParseSeeds("1-2-3").status().message(), HasSubstr("'1-2-3'"));
  EXPECT_EQ(ParseSeeds("").status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(ParseSeeds("-3").status().code(), absl::StatusCode::kInvalidArgument);
}

TEST(SummarizeSweepTest, CountsFailuresInSeedOrderAndSpreadsTheFigures) {
  std::vector<SweepRun> runs;
  std::vector<ScenarioReport> reports;
  for (unsigned seed = 20; seed >= 1; --seed) {  // finished out of order
    SweepRun run;
    run.seed = seed;
    run.passed = seed != 7 && seed != 13;
    if (!run.passed) run.failure = "deadline of 300 s of sim time reached";
    runs.push_back(run);
    ScenarioReport report;
    report.sim_time_s = 100.0 + seed;  // 101 … 120
    report.contacts = seed == 13 ? 2 : 0;
    RobotFigures robot;
    robot.max_loc_error_m = 0.01 * seed;
    report.robots.push_back(robot);
    reports.push_back(report);
  }
  const SweepSummary summary = SummarizeSweep("barn", runs, reports);
  EXPECT_EQ(summary.passed(), 18);
  ASSERT_EQ(summary.runs.size(), 20u);
  EXPECT_EQ(summary.runs.front().seed, 1u);
  EXPECT_EQ(summary.runs[6].seed, 7u);
  EXPECT_FALSE(summary.runs[6].passed);
  // Nearest rank over 20 values: p50 is the 10th, p95 the 19th.
  EXPECT_DOUBLE_EQ(summary.figures.at("sim_time_s").p50, 110.0);
  EXPECT_DOUBLE_EQ(summary.figures.at("sim_time_s").p95, 119.0);
  EXPECT_DOUBLE_EQ(summary.figures.at("sim_time_s").max, 120.0);
  EXPECT_DOUBLE_EQ(summary.figures.at("contacts").max, 2.0);
  EXPECT_DOUBLE_EQ(summary.figures.at("max_loc_error_m").max, 0.2);
  SweepResult sweep;
  sweep.sites.push_back(summary);
  sweep.sites.back().file = "barn.yaml";
  const std::string json = SweepJson(sweep);
  EXPECT_THAT(json, HasSubstr("\"pass_rate\":0.9"));
  EXPECT_THAT(json, HasSubstr("fleetnav-scenario run barn.yaml --seed 13"));
  EXPECT_THAT(json, HasSubstr("{\"cause\":\"deadline of # s of sim time reached\",\"count\":2}"));
}

TEST(FailureCauseTest, TakesOutTheJobTheActionsIndexAndTheNumbers) {
  EXPECT_EQ(FailureCause("job round-7 ended failed (expected succeeded): actions[12] (straight): "
                         "marker 2 was not detected within the action's distance"),
            "job ended failed: straight: marker # was not detected within the action's distance");
  EXPECT_EQ(FailureCause("min separation 0.213 m (at least 0.500 m expected)"),
            "min separation # m (at least # m expected)");
  EXPECT_EQ(FailureCause("job go ended canceled (expected succeeded)"), "job ended canceled");
  // The kind of the action stays: two kinds are two causes.
  EXPECT_NE(FailureCause("job a ended failed (expected succeeded): actions[1] (fence): no fence"),
            FailureCause("job a ended failed (expected succeeded): actions[1] (stripe): no fence"));
}

SweepSummary Site(const std::string& name, const std::vector<std::string>& failures) {
  SweepSummary site;
  site.name = name;
  site.file = name + ".yaml";
  unsigned seed = 1;
  for (const std::string& failure : failures) {
    SweepRun run;
    run.seed = seed++;
    run.passed = failure.empty();
    run.failure = failure;
    site.runs.push_back(run);
  }
  return site;
}

TEST(GroupFailuresTest, GroupsRunsOfEverySiteByCauseMostFrequentFirst) {
  const std::string marker_a =
      "job r ended failed (expected succeeded): actions[3] (straight): marker 2 was not detected";
  const std::string marker_b =
      "job q ended failed (expected succeeded): actions[9] (straight): marker 5 was not detected";
  const std::string touched = "1 contact episode(s) (at most 0 expected)";
  SweepResult sweep;
  sweep.sites = {Site("barn-1", {"", marker_a, touched}), Site("barn-2", {marker_b, "", ""})};
  const std::vector<SweepCause> causes = GroupFailures(sweep.sites);
  ASSERT_EQ(causes.size(), 2u);
  EXPECT_EQ(causes[0].cause, "job ended failed: straight: marker # was not detected");
  ASSERT_EQ(causes[0].runs.size(), 2u);
  EXPECT_EQ(causes[0].runs[0].first, "barn-1.yaml");
  EXPECT_EQ(causes[0].runs[0].second.seed, 2u);
  EXPECT_EQ(causes[0].runs[1].first, "barn-2.yaml");
  EXPECT_EQ(causes[0].runs[1].second.seed, 1u);
  EXPECT_EQ(causes[1].cause, "# contact episode(s) (at most # expected)");
  EXPECT_EQ(sweep.runs(), 6);
  EXPECT_EQ(sweep.passed(), 3);

  const std::string json = SweepJson(sweep);
  EXPECT_THAT(json, HasSubstr("\"sites_passed\":0"));
  EXPECT_THAT(json, HasSubstr("\"pass_rate\":0.5"));
  EXPECT_THAT(json, HasSubstr("fleetnav-scenario run barn-2.yaml --seed 1"));
  EXPECT_THAT(json, HasSubstr("\"count\":2"));
  std::ostringstream text;
  PrintSweep(sweep, text);
  EXPECT_THAT(text.str(), HasSubstr("sweep of 2 sites: 3/6 runs passed (50.0 %)"));
  EXPECT_THAT(text.str(), HasSubstr("   2× job ended failed: straight: marker # was not detected"));
  EXPECT_THAT(text.str(), HasSubstr("barn-2"));
}

}  // namespace
}  // namespace fleetnav::scenario
