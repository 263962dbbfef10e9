#include "fleetnav/planner/mapf/mapf_solver.hpp"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"

namespace fleetnav::planner {

absl::Status MapfStopCondition::Validate() const {
  if (!(time_limit_s > 0.0) || !std::isfinite(time_limit_s)) {
    return absl::InvalidArgumentError("time_limit_s: must be finite and > 0");
  }
  return absl::OkStatus();
}

absl::Status ValidateSolveInput(const MapfInstance& instance, const MapfStopCondition& stop) {
  if (absl::Status s = stop.Validate(); !s.ok()) return s;
  return instance.Validate();
}

double MapfStopwatch::RemainingS(double floor_s) const {
  return std::max(stop_.time_limit_s - ElapsedMs() * 1e-3, floor_s);
}

absl::Status MapfStopwatch::NoPlanStatus(const std::string& solver) const {
  if (StopRequested()) return absl::CancelledError(absl::StrCat(solver, ": stopped before a plan"));
  return absl::DeadlineExceededError(
      absl::StrCat(solver, ": no plan within ", stop_.time_limit_s, " s"));
}

}  // namespace fleetnav::planner
