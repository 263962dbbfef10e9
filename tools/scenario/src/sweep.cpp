#include "fleetnav/scenario/sweep.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <functional>
#include <mutex>
#include <nlohmann/json.hpp>
#include <ostream>
#include <thread>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_split.h"

namespace fleetnav::scenario {
namespace {

FigureSpread Spread(std::vector<double> values) {
  if (values.empty()) return {};
  std::sort(values.begin(), values.end());
  // Nearest rank: the smallest value at or above the share q of the runs.
  const auto at = [&](double q) {
    const auto rank = static_cast<size_t>(std::ceil(q * static_cast<double>(values.size())));
    return values[std::clamp<size_t>(rank, 1, values.size()) - 1];
  };
  return {at(0.5), at(0.95), values.back()};
}

double MaxLocalizationError(const ScenarioReport& report) {
  double worst = 0.0;
  for (const RobotFigures& robot : report.robots) worst = std::max(worst, robot.max_loc_error_m);
  return worst;
}

std::string ReplayCommand(const SweepRun& run, const std::string& scenario_file) {
  std::string command = absl::StrCat("fleetnav-scenario run ", scenario_file, " --seed ", run.seed);
  if (!run.kept_dir.empty()) absl::StrAppend(&command, " --keep ", run.kept_dir);
  return command;
}

}  // namespace

absl::StatusOr<std::vector<unsigned>> ParseSeeds(const std::string& text) {
  std::vector<unsigned> seeds;
  for (const absl::string_view part : absl::StrSplit(text, ',')) {
    const std::vector<absl::string_view> ends = absl::StrSplit(part, '-');
    unsigned first = 0;
    bool parsed = ends.size() <= 2 && absl::SimpleAtoi(ends.front(), &first);
    unsigned last = first;
    if (parsed && ends.size() == 2) parsed = absl::SimpleAtoi(ends[1], &last);
    if (!parsed) {
      return absl::InvalidArgumentError(
          absl::StrCat("--seeds: '", part, "' is neither a seed nor a range A-B"));
    }
    if (last < first) {
      return absl::InvalidArgumentError(
          absl::StrCat("--seeds: the range '", part, "' runs backwards"));
    }
    if (last - first >= 100000) {
      return absl::InvalidArgumentError(
          absl::StrCat("--seeds: the range '", part, "' has more than 100000 seeds"));
    }
    for (unsigned seed = first; seed <= last; ++seed) seeds.push_back(seed);
  }
  return seeds;
}

int SweepSummary::passed() const {
  return static_cast<int>(
      std::count_if(runs.begin(), runs.end(), [](const SweepRun& run) { return run.passed; }));
}

SweepSummary SummarizeSweep(const std::string& name, std::vector<SweepRun> runs,
                            const std::vector<ScenarioReport>& reports) {
  SweepSummary summary;
  summary.name = name;
  std::sort(runs.begin(), runs.end(),
            [](const SweepRun& a, const SweepRun& b) { return a.seed < b.seed; });
  summary.runs = std::move(runs);
  const std::vector<std::pair<std::string, std::function<double(const ScenarioReport&)>>> figures =
      {{"sim_time_s", [](const ScenarioReport& r) { return r.sim_time_s; }},
       {"wall_time_s", [](const ScenarioReport& r) { return r.wall_time_s; }},
       {"min_separation_m", [](const ScenarioReport& r) { return r.min_separation_m; }},
       {"waiting_share", [](const ScenarioReport& r) { return r.waiting_share; }},
       {"max_loc_error_m", MaxLocalizationError},
       {"contacts", [](const ScenarioReport& r) { return static_cast<double>(r.contacts); }}};
  for (const auto& [figure, of] : figures) {
    std::vector<double> values;
    for (const ScenarioReport& report : reports) values.push_back(of(report));
    summary.figures[figure] = Spread(std::move(values));
  }
  return summary;
}

absl::StatusOr<SweepSummary> RunSweep(const Scenario& scenario, const Binaries& binaries,
                                      const SweepOptions& options) {
  if (options.seeds.empty()) return absl::InvalidArgumentError("--seeds: no seed to run");
  if (options.jobs < 1) return absl::InvalidArgumentError("--jobs: must be at least 1");
  std::mutex mutex;
  std::vector<SweepRun> runs;
  std::vector<ScenarioReport> reports;
  std::atomic<size_t> next{0};
  const auto worker = [&] {
    for (size_t i = next++; i < options.seeds.size(); i = next++) {
      SweepRun run;
      run.seed = options.seeds[i];
      RunOptions one = options.run;
      one.seed = run.seed;
      one.progress = nullptr;
      if (!options.keep_failures_dir.empty()) {
        one.keep_dir =
            (std::filesystem::path(options.keep_failures_dir) / absl::StrCat("seed-", run.seed))
                .string();
        std::filesystem::create_directories(one.keep_dir);
      }
      absl::StatusOr<ScenarioReport> report = RunScenario(scenario, binaries, one);
      if (report.ok()) {
        run.passed = report->passed;
        if (!report->failures.empty()) run.failure = report->failures.front();
      } else {
        run.failure = absl::StrCat("the run failed: ", report.status().message());
      }
      if (!one.keep_dir.empty()) {
        if (run.passed) {
          std::filesystem::remove_all(one.keep_dir);
        } else {
          run.kept_dir = one.keep_dir;
        }
      }
      std::lock_guard<std::mutex> lock(mutex);
      if (options.progress != nullptr) {
        *options.progress << absl::StrFormat("seed %u: %s%s\n", run.seed,
                                             run.passed ? "passed" : "FAILED",
                                             run.passed ? "" : ": " + run.failure);
      }
      if (report.ok()) reports.push_back(*std::move(report));
      runs.push_back(std::move(run));
    }
  };
  std::vector<std::thread> threads;
  const int jobs = std::min<int>(options.jobs, static_cast<int>(options.seeds.size()));
  threads.reserve(static_cast<size_t>(jobs));
  for (int j = 0; j < jobs; ++j) threads.emplace_back(worker);
  for (std::thread& thread : threads) thread.join();
  return SummarizeSweep(scenario.name, std::move(runs), reports);
}

void PrintSweep(const SweepSummary& summary, const std::string& scenario_file, std::ostream& out) {
  const int runs = static_cast<int>(summary.runs.size());
  out << absl::StrFormat("sweep %s: %d/%d passed (%.1f %%)\n", summary.name, summary.passed(), runs,
                         runs > 0 ? 100.0 * summary.passed() / runs : 0.0);
  for (const SweepRun& run : summary.runs) {
    if (run.passed) continue;
    out << absl::StrFormat("  seed %u FAILED: %s\n    replay: %s\n", run.seed, run.failure,
                           ReplayCommand(run, scenario_file));
  }
  out << absl::StrFormat("%-18s %12s %12s %12s\n", "FIGURE", "P50", "P95", "MAX");
  for (const auto& [figure, spread] : summary.figures) {
    out << absl::StrFormat("%-18s %12.4g %12.4g %12.4g\n", figure, spread.p50, spread.p95,
                           spread.max);
  }
}

std::string SweepJson(const SweepSummary& summary, const std::string& scenario_file) {
  nlohmann::json json;
  json["name"] = summary.name;
  json["runs"] = summary.runs.size();
  json["passed"] = summary.passed();
  json["pass_rate"] =
      summary.runs.empty() ? 0.0 : static_cast<double>(summary.passed()) / summary.runs.size();
  json["failing"] = nlohmann::json::array();
  for (const SweepRun& run : summary.runs) {
    if (run.passed) continue;
    json["failing"].push_back({{"seed", run.seed},
                               {"failure", run.failure},
                               {"replay", ReplayCommand(run, scenario_file)}});
  }
  for (const auto& [figure, spread] : summary.figures) {
    json["figures"][figure] = {{"p50", spread.p50}, {"p95", spread.p95}, {"max", spread.max}};
  }
  return json.dump();
}

}  // namespace fleetnav::scenario
