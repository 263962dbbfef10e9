#include "fleetnav/scenario/sweep.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iterator>
#include <mutex>
#include <nlohmann/json.hpp>
#include <ostream>
#include <regex>
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

std::map<std::string, FigureSpread> FigureSpreads(const std::vector<ScenarioReport>& reports) {
  const std::vector<std::pair<std::string, std::function<double(const ScenarioReport&)>>> figures =
      {{"sim_time_s", [](const ScenarioReport& r) { return r.sim_time_s; }},
       {"wall_time_s", [](const ScenarioReport& r) { return r.wall_time_s; }},
       {"min_separation_m", [](const ScenarioReport& r) { return r.min_separation_m; }},
       {"waiting_share", [](const ScenarioReport& r) { return r.waiting_share; }},
       {"longest_standstill_s", [](const ScenarioReport& r) { return r.longest_standstill_s; }},
       {"max_loc_error_m", MaxLocalizationError},
       {"contacts", [](const ScenarioReport& r) { return static_cast<double>(r.contacts); }}};
  std::map<std::string, FigureSpread> spreads;
  for (const auto& [figure, of] : figures) {
    std::vector<double> values;
    values.reserve(reports.size());
    for (const ScenarioReport& report : reports) values.push_back(of(report));
    spreads[figure] = Spread(std::move(values));
  }
  return spreads;
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
  summary.figures = FigureSpreads(reports);
  return summary;
}

std::string FailureCause(const std::string& failure) {
  static const std::regex kJob(R"(^job \S+ ended (\S+) \(expected \S+\))");
  static const std::regex kAction(R"(actions\[\d+\] \(([^)]*)\))");
  static const std::regex kNumber(R"(-?\d+(\.\d+)?(e-?\d+)?)");
  std::string cause = std::regex_replace(failure, kJob, "job ended $1");
  cause = std::regex_replace(cause, kAction, "$1");
  return std::regex_replace(cause, kNumber, "#");
}

std::vector<SweepCause> GroupFailures(const std::vector<SweepSummary>& sites) {
  std::map<std::string, SweepCause> by_cause;
  for (const SweepSummary& site : sites) {
    for (const SweepRun& run : site.runs) {
      if (run.passed) continue;
      SweepCause& cause = by_cause[FailureCause(run.failure)];
      cause.runs.emplace_back(site.file, run);
    }
  }
  std::vector<SweepCause> causes;
  causes.reserve(by_cause.size());
  for (auto& [text, cause] : by_cause) {
    cause.cause = text;
    causes.push_back(std::move(cause));
  }
  std::stable_sort(causes.begin(), causes.end(), [](const SweepCause& a, const SweepCause& b) {
    return a.runs.size() > b.runs.size();
  });
  return causes;
}

int SweepResult::runs() const {
  int runs = 0;
  for (const SweepSummary& site : sites) runs += static_cast<int>(site.runs.size());
  return runs;
}

int SweepResult::passed() const {
  int passed = 0;
  for (const SweepSummary& site : sites) passed += site.passed();
  return passed;
}

absl::StatusOr<SweepResult> RunSweep(const std::vector<SweepSite>& sites, const Binaries& binaries,
                                     const SweepOptions& options) {
  if (sites.empty()) return absl::InvalidArgumentError("no scenario file to sweep");
  if (options.seeds.empty()) return absl::InvalidArgumentError("--seeds: no seed to run");
  if (options.jobs < 1) return absl::InvalidArgumentError("--jobs: must be at least 1");
  // Where each site keeps its failing runs: DIR for one site, DIR/NAME (NAME-2 … for repeated
  // names) for several.
  std::vector<std::filesystem::path> keep_dirs;
  std::map<std::string, int> names_seen;
  for (const SweepSite& site : sites) {
    std::filesystem::path dir = options.keep_failures_dir;
    if (sites.size() > 1 && !dir.empty()) {
      const int seen = ++names_seen[site.scenario.name];
      dir /= seen == 1 ? site.scenario.name : absl::StrCat(site.scenario.name, "-", seen);
    }
    keep_dirs.push_back(dir);
  }
  const size_t total = sites.size() * options.seeds.size();
  std::mutex mutex;
  std::vector<std::vector<SweepRun>> runs(sites.size());
  std::vector<std::vector<ScenarioReport>> reports(sites.size());
  size_t finished = 0;
  std::atomic<size_t> next{0};
  const auto worker = [&] {
    for (size_t i = next++; i < total; i = next++) {
      // Seed-major order: the first seed of every site runs before any site's second.
      const size_t site_index = i % sites.size();
      const SweepSite& site = sites[site_index];
      SweepRun run;
      run.seed = options.seeds[i / sites.size()];
      RunOptions one = options.run;
      one.seed = run.seed;
      one.progress = nullptr;
      if (!options.keep_failures_dir.empty()) {
        one.keep_dir = (keep_dirs[site_index] / absl::StrCat("seed-", run.seed)).string();
        std::filesystem::create_directories(one.keep_dir);
      }
      absl::StatusOr<ScenarioReport> report = RunScenario(site.scenario, binaries, one);
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
      ++finished;
      if (options.progress != nullptr) {
        const std::string where = sites.size() > 1
                                      ? absl::StrFormat("[%d/%d] %s seed %u", finished, total,
                                                        site.scenario.name, run.seed)
                                      : absl::StrFormat("seed %u", run.seed);
        *options.progress << absl::StrFormat("%s: %s%s\n", where, run.passed ? "passed" : "FAILED",
                                             run.passed ? "" : ": " + run.failure);
      }
      if (report.ok()) reports[site_index].push_back(*std::move(report));
      runs[site_index].push_back(std::move(run));
    }
  };
  std::vector<std::thread> threads;
  const int jobs = static_cast<int>(std::min<size_t>(static_cast<size_t>(options.jobs), total));
  threads.reserve(static_cast<size_t>(jobs));
  for (int j = 0; j < jobs; ++j) threads.emplace_back(worker);
  for (std::thread& thread : threads) thread.join();
  SweepResult result;
  std::vector<ScenarioReport> every_report;
  for (size_t s = 0; s < sites.size(); ++s) {
    result.sites.push_back(SummarizeSweep(sites[s].scenario.name, std::move(runs[s]), reports[s]));
    result.sites.back().file = sites[s].file;
    std::move(reports[s].begin(), reports[s].end(), std::back_inserter(every_report));
  }
  result.figures = FigureSpreads(every_report);
  return result;
}

namespace {

void PrintFigures(const std::map<std::string, FigureSpread>& figures, std::ostream& out) {
  out << absl::StrFormat("%-18s %12s %12s %12s\n", "FIGURE", "P50", "P95", "MAX");
  for (const auto& [figure, spread] : figures) {
    out << absl::StrFormat("%-18s %12.4g %12.4g %12.4g\n", figure, spread.p50, spread.p95,
                           spread.max);
  }
}

double Percent(int part, int whole) { return whole > 0 ? 100.0 * part / whole : 0.0; }

nlohmann::json FiguresJson(const std::map<std::string, FigureSpread>& figures) {
  nlohmann::json json = nlohmann::json::object();
  for (const auto& [figure, spread] : figures) {
    json[figure] = {{"p50", spread.p50}, {"p95", spread.p95}, {"max", spread.max}};
  }
  return json;
}

nlohmann::json SiteJson(const SweepSummary& summary) {
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
                               {"cause", FailureCause(run.failure)},
                               {"replay", ReplayCommand(run, summary.file)}});
  }
  json["figures"] = FiguresJson(summary.figures);
  return json;
}

}  // namespace

void PrintSweep(const SweepResult& sweep, std::ostream& out) {
  const std::vector<SweepCause> causes = GroupFailures(sweep.sites);
  if (sweep.sites.size() == 1) {
    const SweepSummary& summary = sweep.sites.front();
    const int runs = static_cast<int>(summary.runs.size());
    out << absl::StrFormat("sweep %s: %d/%d passed (%.1f %%)\n", summary.name, summary.passed(),
                           runs, Percent(summary.passed(), runs));
    for (const SweepRun& run : summary.runs) {
      if (run.passed) continue;
      out << absl::StrFormat("  seed %u FAILED: %s\n    replay: %s\n", run.seed, run.failure,
                             ReplayCommand(run, summary.file));
    }
    for (const SweepCause& cause : causes) {
      out << absl::StrFormat("  %3d× %s\n", cause.runs.size(), cause.cause);
    }
    PrintFigures(summary.figures, out);
    return;
  }
  const int sites_passed = static_cast<int>(
      std::count_if(sweep.sites.begin(), sweep.sites.end(), [](const SweepSummary& site) {
        return site.passed() == static_cast<int>(site.runs.size());
      }));
  out << absl::StrFormat(
      "sweep of %d sites: %d/%d runs passed (%.1f %%); %d/%d sites passed every seed\n",
      sweep.sites.size(), sweep.passed(), sweep.runs(), Percent(sweep.passed(), sweep.runs()),
      sites_passed, sweep.sites.size());
  for (const SweepCause& cause : causes) {
    out << absl::StrFormat("%4d× %s\n", cause.runs.size(), cause.cause);
    for (const auto& [file, run] : cause.runs) {
      out << absl::StrFormat("      %s\n", ReplayCommand(run, file));
    }
  }
  PrintFigures(sweep.figures, out);
  out << absl::StrFormat("%-24s %7s %12s %12s %10s %10s\n", "SITE", "PASSED", "SIM_P50_S",
                         "LOC_ERR_MAX", "CONTACTS", "MIN_SEP_M");
  for (const SweepSummary& site : sweep.sites) {
    const auto figure = [&](const char* name) {
      const auto it = site.figures.find(name);
      return it == site.figures.end() ? FigureSpread{} : it->second;
    };
    // One robot has no separation (the report's figure is then huge): shown as "-".
    const double separation_m = figure("min_separation_m").p50;
    out << absl::StrFormat("%-24s %3d/%-3d %12.1f %12.3f %10.0f %10s\n", site.name, site.passed(),
                           site.runs.size(), figure("sim_time_s").p50,
                           figure("max_loc_error_m").max, figure("contacts").max,
                           separation_m < 1e6 ? absl::StrFormat("%.3f", separation_m) : "-");
  }
}

std::string SweepJson(const SweepResult& sweep) {
  const std::vector<SweepCause> causes = GroupFailures(sweep.sites);
  if (sweep.sites.size() == 1) {
    nlohmann::json json = SiteJson(sweep.sites.front());
    json["causes"] = nlohmann::json::array();
    for (const SweepCause& cause : causes) {
      json["causes"].push_back({{"cause", cause.cause}, {"count", cause.runs.size()}});
    }
    return json.dump();
  }
  nlohmann::json json;
  json["sites"] = nlohmann::json::array();
  int sites_passed = 0;
  for (const SweepSummary& site : sweep.sites) {
    nlohmann::json one = SiteJson(site);
    one["file"] = site.file;
    json["sites"].push_back(std::move(one));
    if (site.passed() == static_cast<int>(site.runs.size())) ++sites_passed;
  }
  json["runs"] = sweep.runs();
  json["passed"] = sweep.passed();
  json["pass_rate"] = sweep.runs() == 0 ? 0.0 : static_cast<double>(sweep.passed()) / sweep.runs();
  json["sites_passed"] = sites_passed;
  json["causes"] = nlohmann::json::array();
  for (const SweepCause& cause : causes) {
    nlohmann::json runs = nlohmann::json::array();
    for (const auto& [file, run] : cause.runs) {
      runs.push_back({{"file", file},
                      {"seed", run.seed},
                      {"failure", run.failure},
                      {"replay", ReplayCommand(run, file)}});
    }
    json["causes"].push_back(
        {{"cause", cause.cause}, {"count", cause.runs.size()}, {"runs", std::move(runs)}});
  }
  json["figures"] = FiguresJson(sweep.figures);
  return json.dump();
}

}  // namespace fleetnav::scenario
