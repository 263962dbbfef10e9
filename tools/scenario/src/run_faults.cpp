#include <signal.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "absl/strings/strip.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/clock.hpp"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/proto/channel_credentials.hpp"
#include "fleetnav/proto/geometry_convert.hpp"
#include "fleetnav/proto/server_target.hpp"
#include "fleetnav/proto/sim_convert.hpp"
#include "scenario_run.hpp"

namespace fleetnav::scenario::internal {

void Run::Inject(const ScenarioFault& fault) {
  switch (fault.type) {
    case ScenarioFaultType::kKillAgent:
      if (auto it = agents_.find(fault.robot_id); it != agents_.end()) {
        it->second->Stop(SIGKILL, 5.0);
        agents_cpu_s_ += it->second->cpu_s().value_or(0.0);
        restarts_.push_back({fault.at_s + fault.restart_after_s, fault.robot_id});
      }
      return;
    case ScenarioFaultType::kKillServer:
    case ScenarioFaultType::kKillLeader: {
      size_t replica = 0;
      if (fault.type == ScenarioFaultType::kKillLeader) {
        const std::optional<std::pair<size_t, int64_t>> leader = Leader();
        if (!leader) return;  // none yet: nothing to kill
        replica = leader->first;
        failover_ = PendingFailover{Clock::now(), leader->second};
      }
      ServerProcess& server = servers_[replica];
      server.process->Stop(SIGKILL, 5.0);
      server_cpu_s_ += server.process->cpu_s().value_or(0.0);
      // The registry that counted the time robots stood held is gone: the next one (the server
      // started again, or the replica that takes the site over) counts from zero.
      held_seen_s_.clear();
      restarts_.push_back({fault.at_s + fault.restart_after_s, "", replica});
      return;
    }
    case ScenarioFaultType::kCutLink:
      if (auto it = links_.find(fault.robot_id); it != links_.end()) {
        it->second->Cut();
        link_restores_.push_back({fault.at_s + fault.duration_s, fault.robot_id});
      }
      return;
    case ScenarioFaultType::kStopZone:
    case ScenarioFaultType::kStopAll: {
      const bool zone = fault.type == ScenarioFaultType::kStopZone;
      const absl::Status stopped =
          zone ? Ctl({"stop", "--zone", fault.zone, "--map", s_.map_id, "--reason", "scenario"})
               : Ctl({"stop", "--all", "--reason", "scenario"});
      if (!stopped.ok()) {
        stop_failures_.push_back(
            absl::StrCat("the stop at ", fault.at_s, " s failed: ", stopped.message()));
        return;
      }
      StopWindow window;
      window.start_s = fault.at_s;
      window.end_s = fault.duration_s > 0.0 ? fault.at_s + fault.duration_s : 1e18;
      if (zone) {
        window.zone = fault.zone;
        // The zones in force now: the last put, else the scenario's (fleetnavd knew the zone).
        const ZoneSet* zones = !zones_put_.empty() ? &zones_put_.back().zones
                               : s_.zones          ? &*s_.zones
                                                   : nullptr;
        const Zone* stopped = zones != nullptr ? zones->Find(fault.zone) : nullptr;
        if (stopped == nullptr) {
          stop_failures_.push_back(absl::StrCat("the stop at ", fault.at_s, " s: zone '",
                                                fault.zone, "' is in none of the run's zones"));
          return;
        }
        window.polygon = stopped->polygon_in_map;
      }
      stop_windows_.push_back(window);
      if (fault.duration_s > 0.0) stop_ends_.push_back({window.end_s, window.zone});
      return;
    }
    case ScenarioFaultType::kPutZones: {
      const absl::Status put = Ctl({"zones", "put", "--map", s_.map_id, fault.file});
      if (!put.ok()) {
        stop_failures_.push_back(
            absl::StrCat("the zones put at ", fault.at_s, " s failed: ", put.message()));
        return;
      }
      zones_put_.push_back({fault.at_s, *fault.zones});
      return;
    }
    case ScenarioFaultType::kSimFault: {
      const absl::StatusOr<FaultType> type = FaultTypeByName(fault.sim_type);
      FaultSpec spec;
      if (type.ok()) spec.type = *type;
      spec.robot_id = fault.robot_id;
      spec.sensor_name = fault.sensor;
      spec.duration_s = fault.duration_s;
      spec.factor = fault.factor;
      if (fault.region) {
        spec.region_min_m = fault.region->first.translation();
        spec.region_max_m = fault.region->second.translation();
      }
      v1::InjectFaultRequest request = ToProto(spec);
      // An unknown type (the scenario file's check names it) goes unspecified: the simulator
      // refuses it.
      if (!type.ok()) request.set_type(v1::FAULT_TYPE_UNSPECIFIED);
      grpc::ClientContext context;
      WithDeadline(&context);
      v1::InjectFaultResponse response;
      (void)simulator_->InjectFault(&context, request, &response);
      return;
    }
  }
}

}  // namespace fleetnav::scenario::internal
