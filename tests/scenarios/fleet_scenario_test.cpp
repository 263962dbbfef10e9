// fleetnav-scenario as users run it: the shipped two-robot barn, judged by the simulator's
// ground truth, and scenario files that must be refused before anything starts.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "fleetnav/scenario/child_process.hpp"

namespace fleetnav {
namespace {

using scenario::ChildProcess;
using ::testing::HasSubstr;

std::string TempPath(const std::string& name) {
  return (std::filesystem::path(::testing::TempDir()) / name).string();
}

// Two Lely robots whose routes cross at the feed kitchen: fleetnavd's traffic clearances make
// one wait, both rounds end, and the robots never touch or come closer than 0.5 m.
TEST(FleetScenario, TwoLelyRobotsShareTheBarnWithoutContact) {
  const std::string keep = TempPath("barn-two-lely");
  std::filesystem::remove_all(keep);
  ChildProcess run(
      {FLEETNAV_SCENARIO_PATH, "run", FLEETNAV_SCENARIOS_DIR "/barn_two_lely.yaml", "--json",
       "--keep", keep, "--picture", std::string(FLEETNAV_SCENARIO_OUT_DIR) + "/barn_two_lely.png"},
      TempPath("two.out"), TempPath("two.err"));
  const std::optional<int> code = run.Wait(900.0);
  ASSERT_TRUE(code.has_value()) << "the scenario did not end in 15 min";
  const std::string out = run.Stdout();
  ASSERT_FALSE(out.empty()) << run.Stderr();
  const nlohmann::json report = nlohmann::json::parse(out);
  std::printf("[ figures  ] %s\n", out.c_str());
  EXPECT_EQ(*code, 0) << out << run.Stderr();
  EXPECT_TRUE(report["passed"].get<bool>()) << report["failures"].dump();
  EXPECT_EQ(report["contacts"].get<int>(), 0);
  EXPECT_GE(report["min_separation_m"].get<double>(), 0.5);
  ASSERT_EQ(report["jobs"].size(), 2u);
  for (const auto& job : report["jobs"]) EXPECT_EQ(job["state"], "succeeded") << job.dump();
  // The routes cross: one robot was held by traffic coordination for a while.
  double waited_s = 0.0;
  for (const auto& robot : report["robots"]) {
    EXPECT_EQ(robot["contacts"].get<int>(), 0);
    EXPECT_GT(robot["distance_m"].get<double>(), 20.0);
    waited_s += robot["waiting_s"].get<double>();
  }
  EXPECT_GT(waited_s, 5.0);
  EXPECT_TRUE(std::filesystem::exists(keep + "/truth.csv"));
}

// `job submit --goal`'s job as a robot runs it: one free-navigation action to the goal.
TEST(FleetScenario, AGoalJobEndsAtTheGoal) {
  ChildProcess run(
      {FLEETNAV_SCENARIO_PATH, "run", FLEETNAV_SCENARIOS_DIR "/barn_goal.yaml", "--json"},
      TempPath("goal.out"), TempPath("goal.err"));
  const std::optional<int> code = run.Wait(300.0);
  ASSERT_TRUE(code.has_value());
  ASSERT_FALSE(run.Stdout().empty()) << run.Stderr();
  const nlohmann::json report = nlohmann::json::parse(run.Stdout());
  EXPECT_EQ(*code, 0) << run.Stdout();
  ASSERT_EQ(report["robots"].size(), 1u);
  const nlohmann::json& end = report["robots"][0]["final_pose"];
  EXPECT_NEAR(end["x_m"].get<double>(), -3.0, 0.3) << end.dump();
  EXPECT_NEAR(end["y_m"].get<double>(), 2.0, 0.3) << end.dump();
  EXPECT_NEAR(end["yaw_rad"].get<double>(), M_PI / 2, 0.15) << end.dump();
  EXPECT_EQ(report["contacts"].get<int>(), 0);
}

/// Runs fleetnav-scenario on a scenario text and returns its exit code and its stderr.
std::pair<int, std::string> RunBad(const std::string& name, const std::string& text) {
  const std::string path = TempPath(name);
  std::ofstream(path) << text;
  ChildProcess run({FLEETNAV_SCENARIO_PATH, "run", path}, TempPath(name + ".out"),
                   TempPath(name + ".err"));
  const std::optional<int> code = run.Wait(60.0);
  return {code.value_or(-1), run.Stderr()};
}

const std::string kHead = std::string("world: ") + FLEETNAV_WORLDS_DIR +
                          "/barn_two_lely.yaml\nroutes: [" + FLEETNAV_ROUTES_DIR +
                          "/barn_feeding.yaml]\n";

TEST(FleetScenario, BadScenarioFilesAreRefusedNamingTheFileAndTheKey) {
  {
    const auto [code, err] =
        RunBad("unknown-key.yaml", kHead + "jobs: [{route: barn-feeding, robt: lely1}]\n");
    EXPECT_EQ(code, 2);
    EXPECT_THAT(err, HasSubstr("unknown-key.yaml"));
    EXPECT_THAT(err, HasSubstr("jobs[0].robt: unknown key"));
  }
  {
    const auto [code, err] =
        RunBad("no-robot.yaml", kHead + "jobs: [{route: barn-feeding, robot: lely9}]\n");
    EXPECT_EQ(code, 2);
    EXPECT_THAT(err, HasSubstr("jobs[0].robot: 'lely9'"));
  }
  {
    const auto [code, err] = RunBad(
        "late.yaml", kHead + "jobs: [{route: barn-feeding, at_s: 50}]\nexpect: {deadline_s: 40}\n");
    EXPECT_EQ(code, 2);
    EXPECT_THAT(err, HasSubstr("jobs[0].at_s: 50 s is not before the deadline 40 s"));
  }
  {
    const auto [code, err] = RunBad(
        "world-robot.yaml", kHead + "robots: [{id: store1}]\njobs: [{route: barn-feeding}]\n");
    EXPECT_EQ(code, 2);
    EXPECT_THAT(err, HasSubstr("robots[0].id: 'store1' is not a robot of world barn"));
  }
  {
    const auto [code, err] = RunBad("unknown-route.yaml", kHead + "jobs: [{route: nowhere}]\n");
    EXPECT_EQ(code, 2);
    EXPECT_THAT(err, HasSubstr("jobs[0].route: 'nowhere' is not in the scenario's routes"));
  }
}

}  // namespace
}  // namespace fleetnav
