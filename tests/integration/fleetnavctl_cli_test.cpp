// fleetnavctl as operators and scripts run it: the real binary against a fleetnavd on loopback,
// judged by exit codes (docs/binaries.md), stdout and stderr.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "fleet_fixture.hpp"
#include "fleetnav/core/map_io.hpp"
#include "fleetnav/ctl/progress.hpp"
#include "fleetnav/scenario/child_process.hpp"

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

/// What one fleetnavctl run printed and how it ended.
struct CliRun {
  int exit_code = -1;
  std::string out;
  std::string err;
};

class FleetnavctlCliTest : public testing::FleetServerFixture {
 protected:
  std::string Address() const { return "127.0.0.1:" + std::to_string(port_); }

  CliRun Run(std::vector<std::string> args) {
    args.insert(args.begin(), FLEETNAV_FLEETNAVCTL_PATH);
    const std::string base = testing::UniqueTempPath("ctl-run");
    scenario::ChildProcess child(args, base + ".out", base + ".err");
    EXPECT_TRUE(child.started());
    CliRun run;
    run.exit_code = child.Wait(30.0).value_or(-1);
    run.out = child.Stdout();
    run.err = child.Stderr();
    return run;
  }

  std::string WriteFile(const std::string& name, const std::string& text) {
    const std::string path = testing::UniqueTempPath(name);
    std::ofstream(path) << text;
    return path;
  }
};

TEST(ProgressTest, TheEtaIsTheTimeStillNeededAtThePaceSoFar) {
  // A quarter done after 60 s: 180 s to go.
  EXPECT_EQ(ctl::EtaText(1'000'000, 1'060'000, 0.25), "ETA 3m00s");
  EXPECT_EQ(ctl::EtaText(0, 10'000, 0.5), "ETA 0m10s");
  EXPECT_EQ(ctl::EtaText(0, 3'600'000, 0.4), "ETA 1h30m");
  // Nothing to say before any progress, at the end, or without elapsed time.
  EXPECT_EQ(ctl::EtaText(0, 60'000, 0.0), "");
  EXPECT_EQ(ctl::EtaText(0, 60'000, 1.0), "");
  EXPECT_EQ(ctl::EtaText(5'000, 5'000, 0.5), "");
  EXPECT_EQ(ctl::ProgressBar(0.5), "[###############...............]  50%");
}

TEST_F(FleetnavctlCliTest, ExitCodesSayHowACommandEnded) {
  EXPECT_EQ(Run({"--version"}).exit_code, 0);
  EXPECT_THAT(Run({"--version"}).out, HasSubstr("0.1.0"));
  EXPECT_EQ(Run({}).exit_code, 2);                                        // no command
  EXPECT_EQ(Run({"map", "frobnicate"}).exit_code, 2);                     // unknown command
  EXPECT_EQ(Run({"--server", Address(), "job", "submit"}).exit_code, 2);  // neither route nor goal
  EXPECT_EQ(Run({"--timeout-s", "-1", "robots"}).exit_code, 2);
  // Global flags anywhere on the line.
  const CliRun missing = Run({"job", "get", "job-424242", "--server", Address()});
  EXPECT_EQ(missing.exit_code, 3) << missing.err;
  EXPECT_THAT(missing.err, HasSubstr("job-424242"));
  const std::string bad_route =
      WriteFile("bad-route.yaml", "name: alley\nmap: barn\nactions:\n  - fly: {}\n");
  EXPECT_EQ(Run({"routes", "put", bad_route, "--server", Address()}).exit_code, 4);
  EXPECT_EQ(Run({"--server", Address(), "robots", "forget", "nobody"}).exit_code, 3);
}

TEST_F(FleetnavctlCliTest, AnUnreachableServerIsSaidInOneLine) {
  // Port 1 on loopback: nothing listens there.
  const CliRun run = Run({"--server", "127.0.0.1:1", "--timeout-s", "3", "robots"});
  EXPECT_EQ(run.exit_code, 5);
  EXPECT_EQ(run.err,
            "fleetnavctl: cannot reach fleetnavd at 127.0.0.1:1: connection refused — is it "
            "running?\n");
}

TEST_F(FleetnavctlCliTest, TheServerAddressComesFromTheEnvironment) {
  ASSERT_EQ(setenv("FLEETNAV_SERVER", Address().c_str(), 1), 0);
  const CliRun run = Run({"map", "list", "--json"});
  unsetenv("FLEETNAV_SERVER");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(nlohmann::json::parse(run.out), nlohmann::json::array());
}

TEST_F(FleetnavctlCliTest, JsonForEveryAnswer) {
  absl::StatusOr<OccupancyGrid> grid = OccupancyGrid::Filled(40, 30, 0.1, Pose2(), 0);
  const std::string map_yaml = testing::UniqueTempPath("cli-map") + ".yaml";
  ASSERT_TRUE(SaveMapServer(*grid, map_yaml).ok());
  const auto json_of = [&](std::vector<std::string> args) {
    args.push_back("--json");
    args.push_back("--server=" + Address());
    const CliRun run = Run(args);
    EXPECT_EQ(run.exit_code, 0) << run.err;
    return nlohmann::json::parse(run.out);
  };
  EXPECT_EQ(json_of({"map", "import", "--id", "barn", map_yaml})["version"], 1);
  const std::string markers =
      WriteFile("cli-markers.yaml",
                "map: barn\nmarkers:\n  - id: 1\n    position: {x: 1.0, y: 1.0, z: 0.0}\n"
                "    orientation: {a: 0.0, b: 0.0, c: 0.0, d: 1.0}\n");
  EXPECT_EQ(json_of({"markers", "put", markers})["version"], 1);
  EXPECT_EQ(json_of({"markers", "get", "--map", "barn"})["version"], 1);
  const std::string route = WriteFile(
      "cli-route.yaml", "name: alley\nmap: barn\nactions:\n  - straight: {distance: 1.0}\n");
  EXPECT_EQ(json_of({"routes", "put", route})["actions"], 1);
  const nlohmann::json got = json_of({"routes", "get", "alley"});
  EXPECT_EQ(got["route"]["name"], "alley");
  EXPECT_EQ(got["version"], 1);
  const nlohmann::json job = json_of({"job", "submit", "--route", "alley"});
  const std::string job_id = job["job_id"];
  EXPECT_EQ(json_of({"job", "cancel", job_id})["state"], "cancelled");
  EXPECT_EQ(json_of({"map", "export", "--id", "barn", map_yaml + ".out.yaml"})["version"], 1);
  // The same route again is its version 1; deleted, it is gone, and the map can go.
  EXPECT_EQ(json_of({"routes", "put", route})["version"], 1);
  EXPECT_EQ(json_of({"routes", "delete", "alley"})["deleted"], "alley");
  EXPECT_EQ(Run({"routes", "get", "alley", "--server", Address()}).exit_code, 3);
  EXPECT_EQ(Run({"routes", "delete", "alley", "--server", Address()}).exit_code, 3);
  EXPECT_EQ(json_of({"markers", "delete", "--map", "barn"})["deleted_markers_of"], "barn");
  EXPECT_EQ(Run({"markers", "get", "--map", "barn", "--server", Address()}).exit_code, 3);
  EXPECT_EQ(json_of({"map", "delete", "--id", "barn"})["deleted"], "barn");
}

TEST_F(FleetnavctlCliTest, MapRenderDrawsTheSiteIntoAPng) {
  absl::StatusOr<OccupancyGrid> grid = OccupancyGrid::Filled(60, 40, 0.1, Pose2(), 0);
  const std::string map_yaml = testing::UniqueTempPath("render-map") + ".yaml";
  ASSERT_TRUE(SaveMapServer(*grid, map_yaml).ok());
  const std::string server = "--server=" + Address();
  ASSERT_EQ(Run({"map", "import", "--id", "yard", map_yaml, server}).exit_code, 0);
  const std::string markers =
      WriteFile("render-markers.yaml",
                "map: yard\nmarkers:\n  - id: 1\n    position: {x: 1.0, y: 1.0, z: 0.0}\n"
                "    orientation: {a: 0.0, b: 0.0, c: 0.0, d: 1.0}\n");
  ASSERT_EQ(Run({"markers", "put", markers, server}).exit_code, 0);
  const std::string route =
      WriteFile("render-route.yaml",
                "name: lap\nmap: yard\nactions:\n"
                "  - free_navigation: {waypoints: [[1, 2]], goal: {x: 4, y: 2, yaw_deg: 0}}\n");
  ASSERT_EQ(Run({"routes", "put", route, server}).exit_code, 0);

  const std::string png = testing::UniqueTempPath("yard") + ".png";
  const CliRun run =
      Run({"map", "render", "yard", png, "--pixels-per-cell", "5", "--json", server});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json said = nlohmann::json::parse(run.out);
  EXPECT_EQ(said["width_px"], 300);
  EXPECT_EQ(said["height_px"], 200);
  EXPECT_EQ(said["markers"], 1);
  EXPECT_EQ(said["routes"], 1);
  std::ifstream file(png, std::ios::binary);
  std::string magic(8, '\0');
  file.read(magic.data(), 8);
  EXPECT_EQ(magic, "\x89PNG\r\n\x1a\n");

  // An unknown map is "not found"; a scale out of range and a non-PNG name are usage errors.
  EXPECT_EQ(Run({"map", "render", "nowhere", png, server}).exit_code, 3);
  EXPECT_EQ(Run({"map", "render", "yard", png, "--pixels-per-cell", "0", server}).exit_code, 2);
  const CliRun svg = Run({"map", "render", "yard", png + ".svg", server});
  EXPECT_EQ(svg.exit_code, 2);
  EXPECT_THAT(svg.err, HasSubstr(".png"));
}

TEST_F(FleetnavctlCliTest, BashCompletesCommandsAndFlagsAtEachLevel) {
  const CliRun script = Run({"completion", "bash"});
  ASSERT_EQ(script.exit_code, 0) << script.err;
  const std::string path = WriteFile("fleetnavctl.bash", script.out);
  // What bash offers after the words typed so far (the last one being completed).
  const auto offered = [&](const std::string& words) {
    const std::string probe =
        WriteFile("probe.sh", "source " + path + "\nCOMP_WORDS=(" + words +
                                  ")\nCOMP_CWORD=$((${#COMP_WORDS[@]} - 1))\n_fleetnavctl\n"
                                  "echo \"${COMPREPLY[*]}\"\n");
    const std::string base = testing::UniqueTempPath("bash");
    scenario::ChildProcess bash({"/bin/bash", probe}, base + ".out", base + ".err");
    EXPECT_EQ(bash.Wait(10.0).value_or(-1), 0) << bash.Stderr();
    std::string out = bash.Stdout();
    if (!out.empty() && out.back() == '\n') out.pop_back();
    return out;
  };
  EXPECT_EQ(offered("fleetnavctl ro"), "routes robots");
  EXPECT_EQ(offered("fleetnavctl routes d"), "delete");
  EXPECT_EQ(offered("fleetnavctl --json routes --server x d"), "delete");
  EXPECT_EQ(offered("fleetnavctl job submit --ro"), "--route --robot");
  EXPECT_EQ(offered("fleetnavctl job get --ser"), "--server");  // a global flag, anywhere
  EXPECT_EQ(offered("fleetnavctl --js"), "--json");
  EXPECT_EQ(offered("fleetnavctl map export --v"), "--version");  // once, though global too
  EXPECT_EQ(Run({"completion", "fish"}).exit_code, 2);
}

}  // namespace
}  // namespace fleetnav
