// fleetnav-scenario sweep's pure parts: the seed list and the summary of finished runs.
#include "fleetnav/scenario/sweep.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

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
  const std::string json = SweepJson(summary, "barn.yaml");
  EXPECT_THAT(json, HasSubstr("\"pass_rate\":0.9"));
  EXPECT_THAT(json, HasSubstr("fleetnav-scenario run barn.yaml --seed 13"));
}

}  // namespace
}  // namespace fleetnav::scenario
