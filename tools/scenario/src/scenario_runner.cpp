#include "fleetnav/scenario/scenario_runner.hpp"

#include <filesystem>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/scenario/child_process.hpp"
#include "scenario_run.hpp"

namespace fleetnav::scenario {
namespace internal {

absl::StatusOr<ScenarioReport> Run::Execute() {
  const Clock::time_point wall_start = Clock::now();
  seed_ = opt_.seed.value_or(s_.seed);
  keep_ = !opt_.keep_dir.empty();
  RETURN_IF_ERROR(PrepareWorkFolder());
  StartOutcomes();
  RETURN_IF_ERROR(StartSimulator());
  RETURN_IF_ERROR(StartServers());
  RETURN_IF_ERROR(LoadSite());
  RETURN_IF_ERROR(StartAgents());
  ASSIGN_OR_RETURN(const double sim_s, Drive(wall_start));

  ScenarioReport report;
  report.name = s_.name;
  report.seed = seed_;
  report.sim_time_s = sim_s;
  report.failovers_s = failovers_s_;
  ReadGroundTruth(&report);  // before anything stops
  StopProcesses(&report);
  // A single fleetnavd logs its dispatcher's figures at exit (replicas do not).
  ReadAssigningPasses(ReadWholeFile(ServerLog(0, servers_[0].starts)), &report);
  report.wall_time_s = SecondsSince(wall_start);
  report.real_time_factor = report.wall_time_s > 0 ? report.sim_time_s / report.wall_time_s : 0;
  Finish(&report);
  return report;
}

}  // namespace internal

namespace fs = std::filesystem;

absl::StatusOr<Binaries> Binaries::Find(const std::string& self) {
  const fs::path dir = fs::absolute(fs::path(self)).parent_path();
  Binaries b;
  const std::pair<std::string*, std::pair<const char*, const char*>> wanted[] = {
      {&b.server, {"fleetnavd", "server"}},
      {&b.sim, {"fleetnav-sim", "sim"}},
      {&b.agent, {"fleetnav-agent", "robot_agent"}},
      {&b.ctl, {"fleetnavctl", "tools"}}};
  for (const auto& [slot, names] : wanted) {
    for (const fs::path& candidate :
         {dir / names.first, dir.parent_path() / names.second / names.first}) {
      if (fs::exists(candidate)) {
        *slot = candidate.string();
        break;
      }
    }
    if (slot->empty()) {
      return absl::NotFoundError(absl::StrCat(names.first, " was not found next to ", self,
                                              " nor in the build tree beside it"));
    }
  }
  return b;
}

absl::StatusOr<ScenarioReport> RunScenario(const Scenario& scenario, const Binaries& binaries,
                                           const RunOptions& options) {
  internal::Run run(scenario, binaries, options);
  return run.Execute();
}

}  // namespace fleetnav::scenario
