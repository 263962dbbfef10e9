// fleetnav-scenario: runs a multi-robot scenario file with the real binaries and judges it by
// the simulator's ground truth (docs/scenarios.md).
//
// Exit codes: 0 every expectation held; 1 an expectation failed; 2 bad usage or a bad scenario
// file; 3 the run itself failed (a program did not start).

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <iostream>

#include "fleetnav/core/version.hpp"
#include "fleetnav/scenario/scenario.hpp"
#include "fleetnav/scenario/scenario_runner.hpp"
#include "fleetnav/scenario/sweep.hpp"

namespace {

/// Says what went wrong on stderr and returns the exit code.
int Fail(const absl::Status& status, int exit_code) {
  std::cerr << "fleetnav-scenario: " << status.message() << "\n";
  return exit_code;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"fleetnav-scenario: run a multi-robot scenario in the simulator and check it"};
  app.set_version_flag("--version", std::string(fleetnav::Version()));
  app.require_subcommand(1);
  CLI::App* run = app.add_subcommand("run", "run a scenario file");
  CLI::App* sweep = app.add_subcommand(
      "sweep",
      "run scenario files (one or many sites) once per seed and print the pass rate, the "
      "failures grouped by cause (each with the command that replays it), the figures' "
      "p50/p95/max and, for several files, one line per site");
  std::string file;
  std::vector<std::string> sweep_files;
  bool json = false;
  double timeout_s = 3600.0;
  int agent_niceness = fleetnav::scenario::RunOptions().agent_niceness;
  int sim_niceness = fleetnav::scenario::RunOptions().sim_niceness;
  std::string db;
  run->add_option("FILE", file, "scenario YAML (docs/scenarios.md)")->required();
  sweep->add_option("FILE", sweep_files, "scenario YAML files (docs/scenarios.md)")->required();
  for (CLI::App* command : {run, sweep}) {
    command->add_flag("--json", json, "print one JSON object instead of the tables");
    command->add_option("--wall-timeout-s", timeout_s, "give up a run after this much wall time")
        ->capture_default_str();
    command
        ->add_option("--agent-niceness", agent_niceness,
                     "nice value of the agent processes, which on a site run on the robots' own "
                     "computers (0 = the runner's priority)")
        ->check(CLI::Range(0, 19))
        ->capture_default_str();
    command->add_option("--db", db,
                        "fleetnavd's database: a postgresql://USER@HOST:PORT/DB URI of an empty "
                        "database (needed for scenarios with replicas) [a fresh SQLite file]");
    command
        ->add_option("--sim-niceness", sim_niceness,
                     "nice value of the simulator, which stands for the world (0 = the runner's "
                     "priority)")
        ->check(CLI::Range(0, 19))
        ->capture_default_str();
  }
  unsigned seed = 0;
  CLI::Option* seed_option = run->add_option("--seed", seed, "overrides the scenario's seed");
  std::string picture;
  run->add_option("--picture", picture,
                  "draw the map and the true and estimated paths (.png/.svg)");
  std::string keep;
  run->add_option("--keep", keep, "keep logs, database and recordings in this folder");
  std::string seeds_text;
  sweep->add_option("--seeds", seeds_text, "the seeds: a range 1-100, a list 1,5,9, or both")
      ->required();
  int jobs = 1;
  sweep->add_option("--jobs", jobs, "runs at once (each is a whole fleet of processes)")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  std::string keep_failures;
  sweep->add_option("--keep-failures", keep_failures,
                    "keep each failing run in DIR/seed-N for its replay command");
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help, --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;
  }
  absl::StatusOr<fleetnav::scenario::Binaries> binaries =
      fleetnav::scenario::Binaries::Find(argv[0]);
  fleetnav::scenario::RunOptions options;
  options.wall_timeout_s = timeout_s;
  options.agent_niceness = agent_niceness;
  options.sim_niceness = sim_niceness;
  options.db = db;
  if (sweep->parsed()) {
    std::vector<fleetnav::scenario::SweepSite> sites;
    for (const std::string& sweep_file : sweep_files) {
      absl::StatusOr<fleetnav::scenario::Scenario> scenario =
          fleetnav::scenario::LoadScenario(sweep_file);
      if (!scenario.ok()) return Fail(scenario.status(), 2);
      sites.push_back({sweep_file, *std::move(scenario)});
    }
    absl::StatusOr<std::vector<unsigned>> seeds = fleetnav::scenario::ParseSeeds(seeds_text);
    if (!seeds.ok()) return Fail(seeds.status(), 2);
    if (!binaries.ok()) return Fail(binaries.status(), 3);
    fleetnav::scenario::SweepOptions sweep_options;
    sweep_options.run = options;
    sweep_options.seeds = *std::move(seeds);
    sweep_options.jobs = jobs;
    sweep_options.keep_failures_dir = keep_failures;
    sweep_options.progress = &std::cerr;
    absl::StatusOr<fleetnav::scenario::SweepResult> sweep_result =
        fleetnav::scenario::RunSweep(sites, *binaries, sweep_options);
    if (!sweep_result.ok()) return Fail(sweep_result.status(), 2);
    if (json) {
      std::cout << fleetnav::scenario::SweepJson(*sweep_result) << "\n";
    } else {
      fleetnav::scenario::PrintSweep(*sweep_result, std::cout);
    }
    return sweep_result->passed() == sweep_result->runs() ? 0 : 1;
  }
  absl::StatusOr<fleetnav::scenario::Scenario> scenario = fleetnav::scenario::LoadScenario(file);
  if (!scenario.ok()) return Fail(scenario.status(), 2);
  if (!binaries.ok()) return Fail(binaries.status(), 3);
  if (*seed_option) options.seed = seed;
  options.keep_dir = keep;
  options.picture_path = picture;
  options.progress = &std::cerr;
  options.progress_is_terminal = isatty(STDERR_FILENO) != 0;
  absl::StatusOr<fleetnav::scenario::ScenarioReport> report =
      fleetnav::scenario::RunScenario(*scenario, *binaries, options);
  if (!report.ok()) {
    return Fail(report.status(), 3);
  }
  if (json) {
    std::cout << fleetnav::scenario::ReportJson(*report) << "\n";
  } else {
    fleetnav::scenario::PrintReport(*report, std::cout);
  }
  return report->passed ? 0 : 1;
}
