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
#include "scenario_run.hpp"

namespace fleetnav::scenario::internal {

namespace {

v1::FaultType SimFaultType(const std::string& name) {
  if (name == "hide_ultrasonic") return v1::FAULT_TYPE_HIDE_ULTRASONIC_REGION;
  if (name == "remove_fence") return v1::FAULT_TYPE_REMOVE_FENCE_SEGMENT;
  if (name == "remove_stripe") return v1::FAULT_TYPE_REMOVE_STRIPE_SEGMENT;
  if (name == "wheel_slip") return v1::FAULT_TYPE_WHEEL_SLIP_REGION;
  if (name == "sensor_dropout") return v1::FAULT_TYPE_SENSOR_DROPOUT;
  if (name == "slow_down") return v1::FAULT_TYPE_SLOW_DOWN;
  return v1::FAULT_TYPE_UNSPECIFIED;
}

}  // namespace

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
    case ScenarioFaultType::kSimFault: {
      v1::InjectFaultRequest request;
      request.set_type(SimFaultType(fault.sim_type));
      request.set_robot_id(fault.robot_id);
      request.set_sensor_name(fault.sensor);
      request.set_duration_s(fault.duration_s);
      request.set_factor(fault.factor);
      if (fault.region) {
        request.mutable_region_min()->set_x_m(fault.region->first.x_m());
        request.mutable_region_min()->set_y_m(fault.region->first.y_m());
        request.mutable_region_max()->set_x_m(fault.region->second.x_m());
        request.mutable_region_max()->set_y_m(fault.region->second.y_m());
      }
      grpc::ClientContext context;
      WithDeadline(&context);
      v1::InjectFaultResponse response;
      (void)simulator_->InjectFault(&context, request, &response);
      return;
    }
  }
}

}  // namespace fleetnav::scenario::internal
