#pragma once

#include <iosfwd>
#include <map>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/scenario/scenario.hpp"
#include "fleetnav/scenario/scenario_runner.hpp"

namespace fleetnav::scenario {

/// Seeds from "1-100" (a range), "1,5,9" (a list), "7" or a mix ("1-3,9"); InvalidArgument
/// naming the part that is not one, or a range that runs backwards.
absl::StatusOr<std::vector<unsigned>> ParseSeeds(const std::string& text);

/// The 50th and 95th percentiles and the largest value of one figure over a sweep's runs.
struct FigureSpread {
  double p50 = 0.0;
  double p95 = 0.0;
  double max = 0.0;
};

/// What one seed of a sweep gave: passed, or the first expectation that failed (or why the
/// run itself failed), and where the run was kept for replay ("" when not kept).
struct SweepRun {
  unsigned seed = 0;
  bool passed = false;
  std::string failure;
  std::string kept_dir;
};

/// A sweep's findings: how many runs passed, which seeds failed and why, and the spread of the
/// figures that tell a flaky behaviour (sim_time_s, wall_time_s, min_separation_m,
/// waiting_share, max_loc_error_m, contacts) over the runs that produced a report.
struct SweepSummary {
  std::string name;
  std::vector<SweepRun> runs;  ///< in seed order
  std::map<std::string, FigureSpread> figures;
  int passed() const;
};

/// Summarizes finished runs (the seeds' reports; a run that produced no report counts as
/// failed with `failure` set and no figures).
SweepSummary SummarizeSweep(const std::string& name, std::vector<SweepRun> runs,
                            const std::vector<ScenarioReport>& reports);

struct SweepOptions {
  RunOptions run;  ///< seed, keep_dir and progress are set per run
  std::vector<unsigned> seeds;
  int jobs = 1;  ///< runs at once
  /// Keep each failing run here as seed-N (passing runs are removed); "" keeps none.
  std::string keep_failures_dir;
  std::ostream* progress = nullptr;  ///< one line per finished run
};

/// Runs the scenario once per seed, `jobs` runs at a time (each with its own processes and
/// ports), and summarizes them. InvalidArgument for no seeds or jobs < 1.
absl::StatusOr<SweepSummary> RunSweep(const Scenario& scenario, const Binaries& binaries,
                                      const SweepOptions& options);

/// The summary for people: pass rate, each failing seed with its reason and the command that
/// replays it (`fleetnav-scenario run FILE --seed N [--keep DIR]`), then the figures' spread.
void PrintSweep(const SweepSummary& summary, const std::string& scenario_file, std::ostream& out);
/// The same as one JSON object: {name, runs, passed, pass_rate, failing: [{seed, failure,
/// replay}], figures: {NAME: {p50, p95, max}}}.
std::string SweepJson(const SweepSummary& summary, const std::string& scenario_file);

}  // namespace fleetnav::scenario
