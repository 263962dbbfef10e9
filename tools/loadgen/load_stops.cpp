#include "load_stops.hpp"

#include <algorithm>
#include <chrono>
#include <limits>
#include <thread>

#include "fleetnav/v1/fleet_service.grpc.pb.h"
#include "load_agents.hpp"

namespace fleetnav::loadgen {
namespace {

void SleepUntil(int64_t steady_ns) {
  const int64_t wait_ns = steady_ns - SteadyNowNs();
  if (wait_ns > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(wait_ns));
}

}  // namespace

std::vector<StopRound> RunStopRounds(const LoadTarget& target, int rounds, int64_t first_ns,
                                     int64_t every_ns) {
  auto fleet = v1::FleetService::NewStub(NewOperatorChannel(target, 900000));
  std::vector<StopRound> out;
  for (int k = 0; k < rounds; ++k) {
    SleepUntil(first_ns + k * every_ns);
    v1::StopRobotsRequest stop;
    stop.mutable_scope()->set_whole_fleet(true);
    stop.set_reason("fleetnav-loadgen stop round");
    v1::StopRobotsResponse stopped;
    grpc::ClientContext context;
    StopRound round;
    round.call_ns = SteadyNowNs();
    const grpc::Status status = fleet->StopRobots(&context, stop, &stopped);
    round.return_ns = SteadyNowNs();
    round.ok = status.ok();
    round.error = status.error_message();
    out.push_back(round);
    SleepUntil(first_ns + k * every_ns + every_ns / 2);
    v1::ResumeRobotsRequest resume;
    resume.mutable_scope()->set_whole_fleet(true);
    v1::ResumeRobotsResponse resumed;
    grpc::ClientContext resume_context;
    (void)fleet->ResumeRobots(&resume_context, resume, &resumed);
  }
  return out;
}

StopLatency MeasureStopLatency(const std::vector<StopRound>& rounds,
                               const std::vector<std::pair<int, int64_t>>& heard, int agents) {
  StopLatency out;
  for (size_t k = 0; k < rounds.size(); ++k) {
    const StopRound& round = rounds[k];
    if (!round.ok) continue;
    out.rpc_ms.push_back(static_cast<double>(round.return_ns - round.call_ns) * 1e-6);
    const int64_t until_ns =
        k + 1 < rounds.size() ? rounds[k + 1].call_ns : std::numeric_limits<int64_t>::max();
    std::vector<int64_t> first(agents, std::numeric_limits<int64_t>::max());
    for (const auto& [agent, at_ns] : heard) {
      if (agent < 0 || agent >= agents || at_ns < round.call_ns || at_ns >= until_ns) continue;
      first[agent] = std::min(first[agent], at_ns);
    }
    for (const int64_t at_ns : first) {
      if (at_ns == std::numeric_limits<int64_t>::max()) {
        ++out.missed;
        continue;
      }
      ++out.heard;
      out.from_return_ms.push_back(static_cast<double>(at_ns - round.return_ns) * 1e-6);
    }
  }
  return out;
}

}  // namespace fleetnav::loadgen
