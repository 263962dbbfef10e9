#pragma once

#include <chrono>
#include <functional>
#include <stop_token>
#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/planner/mapf/mapf.hpp"

namespace fleetnav::planner {

/// When a MAPF solver must return: once `time_limit_s` of computation has passed since Solve
/// began, or once `token` is stopped, whichever comes first — OMPL's planner termination
/// condition as data. A solver then returns the best plan it has, or DeadlineExceeded /
/// Cancelled when it has none. The budget is computing time (steady clock), not robot time.
struct MapfStopCondition {
  double time_limit_s = 1.0;  ///< > 0 and finite
  std::stop_token token;

  absl::Status Validate() const;
};

/// Called by a solver with its first plan and then with each plan that improves on the last
/// one, while it keeps searching: an anytime solver's caller can act on the first plan at
/// once. Runs on the solving thread; it may stop the token to end the search.
using MapfPlanObserver = std::function<void(const MapfResult&)>;

/// A multi-agent path finding solver on a grid graph: instance in, plan or status out, a stop
/// condition as input. Every plan returned or observed passes ValidateSolution (no vertex, edge
/// or swap conflicts; each agent ends at its goal). Errors: InvalidArgument (bad instance or
/// parameters, named), DeadlineExceeded or Cancelled (stopped before a plan), NotFound (the
/// solver proved there is no plan), ResourceExhausted (a memory cap hit before a plan).
/// Implementations: LacamSolver, EecbsSolver, MapfPlanner; tests/unit/planner/mapf/
/// mapf_solver_conformance_test.cpp runs every one on the same instances. One Solve at a time
/// per object.
class MapfSolver {
 public:
  virtual ~MapfSolver() = default;
  /// Short lower-case name, as in MapfResult::solver ("lacam", "eecbs", "auto").
  virtual std::string Name() const = 0;
  /// w when every plan's sum of costs is at most w × the optimum; 0 when nothing is promised.
  virtual double SuboptimalityBound() const = 0;
  virtual absl::StatusOr<MapfResult> Solve(const MapfInstance& instance,
                                           const MapfStopCondition& stop,
                                           const MapfPlanObserver& on_plan = nullptr) = 0;
};

/// What every MapfSolver checks before it searches: the stop condition, then the instance
/// (InvalidArgument naming the field).
absl::Status ValidateSolveInput(const MapfInstance& instance, const MapfStopCondition& stop);

/// The running side of a MapfStopCondition: started when a Solve begins, asked by its loops.
class MapfStopwatch {
 public:
  explicit MapfStopwatch(const MapfStopCondition& stop)
      : stop_(stop), started_(std::chrono::steady_clock::now()) {}

  double ElapsedMs() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started_)
        .count();
  }
  /// Budget left in seconds, never below `floor_s`.
  double RemainingS(double floor_s = 0.0) const;
  bool StopRequested() const { return stop_.token.stop_requested(); }
  bool ShouldStop() const { return StopRequested() || ElapsedMs() > stop_.time_limit_s * 1e3; }
  /// Cancelled when the token was stopped, else DeadlineExceeded; both name `solver`.
  absl::Status NoPlanStatus(const std::string& solver) const;
  /// The condition for a sub-search that may use what is left, down to `floor_s`.
  MapfStopCondition Remaining(double floor_s = 1e-3) const {
    return {RemainingS(floor_s), stop_.token};
  }
  const MapfStopCondition& condition() const { return stop_; }

 private:
  MapfStopCondition stop_;
  std::chrono::steady_clock::time_point started_;
};

}  // namespace fleetnav::planner
