#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "load_tls.hpp"

// fleetnav-loadgen's stop rounds: an operator stops the whole fleet and clears the stop again,
// while the agents record when each hears it (docs/server.md, "Stops").

namespace fleetnav::loadgen {

/// One stop of the whole fleet: when StopRobots was called and returned (steady ns).
struct StopRound {
  int64_t call_ns = 0;
  int64_t return_ns = 0;
  bool ok = false;
  std::string error;  ///< the status message when not ok
};

/// Stops the whole fleet `rounds` times, `every_ns` apart from `first_ns` (StopRobots), each
/// cleared half-way to the next (ResumeRobots). Blocking; an operator of its own.
std::vector<StopRound> RunStopRounds(const LoadTarget& target, int rounds, int64_t first_ns,
                                     int64_t every_ns);

/// How soon the agents heard the stops.
struct StopLatency {
  int heard = 0;   ///< (round, agent) pairs in which the agent heard the stop
  int missed = 0;  ///< pairs of a round that succeeded in which it did not, before the next
  /// Heard minus the RPC's return, per heard pair (negative: heard before the return).
  std::vector<double> from_return_ms;
  std::vector<double> rpc_ms;  ///< StopRobots' call to return, per round that succeeded
};

/// Matches each agent's first stop heard at or after a round's call (and before the next
/// round's) to that round. `heard`: (agent index, steady ns); agents 0..agents-1.
StopLatency MeasureStopLatency(const std::vector<StopRound>& rounds,
                               const std::vector<std::pair<int, int64_t>>& heard, int agents);

}  // namespace fleetnav::loadgen
