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

/// A sweep's findings on one scenario file: how many runs passed, which seeds failed and why,
/// and the spread of the figures that tell a flaky behaviour (sim_time_s, wall_time_s,
/// min_separation_m, waiting_share, longest_standstill_s, max_loc_error_m, contacts) over the runs
/// that produced a report.
struct SweepSummary {
  std::string name;
  std::string file;            ///< the scenario file as given on the command line
  std::vector<SweepRun> runs;  ///< in seed order
  std::map<std::string, FigureSpread> figures;
  int passed() const;
};

/// Summarizes finished runs (the seeds' reports; a run that produced no report counts as
/// failed with `failure` set and no figures).
SweepSummary SummarizeSweep(const std::string& name, std::vector<SweepRun> runs,
                            const std::vector<ScenarioReport>& reports);

/// A failure with what differs between sites and seeds taken out, so that failures of one kind
/// group together: the job's name, the action's index (its kind stays) and every number
/// (written `#`). "job round-7 ended failed (expected succeeded): actions[7] (straight): marker
/// 2 was not detected" becomes "job ended failed: straight: marker # was not detected".
std::string FailureCause(const std::string& failure);

/// One cause of failure over a sweep: how many runs failed of it and which (scenario file,
/// seed) they were.
struct SweepCause {
  std::string cause;
  std::vector<std::pair<std::string, SweepRun>> runs;  ///< (scenario file, run)
};

/// The failing runs of every site grouped by `FailureCause`, the most frequent cause first
/// (ties in the order of the cause's text).
std::vector<SweepCause> GroupFailures(const std::vector<SweepSummary>& sites);

/// A scenario file of a sweep, loaded.
struct SweepSite {
  std::string file;  ///< as given on the command line (for the replay command)
  Scenario scenario;
};

struct SweepOptions {
  RunOptions run;  ///< seed, keep_dir and progress are set per run
  std::vector<unsigned> seeds;
  int jobs = 1;  ///< runs at once
  /// Keep each failing run here as seed-N (one site) or NAME/seed-N (several; NAME the
  /// scenario's name); passing runs are removed. "" keeps none.
  std::string keep_failures_dir;
  std::ostream* progress = nullptr;  ///< one line per finished run
};

/// A whole sweep: each site's summary (in the order given) and the figures' spread over every
/// run of every site.
struct SweepResult {
  std::vector<SweepSummary> sites;
  std::map<std::string, FigureSpread> figures;
  int runs() const;
  int passed() const;
};

/// Runs every site once per seed, `jobs` runs at a time (each with its own processes and
/// ports; the sites' runs interleave), and summarizes each site and the whole.
/// InvalidArgument for no site, no seeds or jobs < 1.
absl::StatusOr<SweepResult> RunSweep(const std::vector<SweepSite>& sites, const Binaries& binaries,
                                     const SweepOptions& options);

/// The summary for people. One site: pass rate, each failing seed with its reason and the
/// command that replays it (`fleetnav-scenario run FILE --seed N [--keep DIR]`), the failures
/// by cause, then the figures' spread. Several: the pass rate over all runs and sites, the
/// failures by cause (each run with its replay command), the figures over all runs, and one
/// line per site.
void PrintSweep(const SweepResult& sweep, std::ostream& out);
/// The same as one JSON object. One site: {name, runs, passed, pass_rate, failing: [{seed,
/// failure, cause, replay}], causes: [{cause, count}], figures: {NAME: {p50, p95, max}}}.
/// Several: {sites: [the one-site object plus `file`, without `causes`], runs, passed,
/// pass_rate, sites_passed, causes: [{cause, count, runs: [{file, seed, failure, replay}]}],
/// figures}.
std::string SweepJson(const SweepResult& sweep);

}  // namespace fleetnav::scenario
