#include "fleetnav/robot_agent/control/modes/undock_controller.hpp"

#include <algorithm>

#include "absl/strings/str_cat.h"

namespace fleetnav::agent {

ControlOutput UndockController::Step(const ControlInput& input) {
  ControlOutput out;
  out.mode = NavigationMode::kDocking;
  out.lift_raised = false;
  if (!input.perception.lift_loaded) {
    out.done = true;
    out.progress_fraction = 1.0;
    return out;
  }
  lowering_s_ += input.dt_s;
  out.progress_fraction = timeout_s_ > 0.0 ? std::min(0.99, lowering_s_ / timeout_s_) : 0.0;
  if (lowering_s_ > timeout_s_) {
    out.failure = absl::FailedPreconditionError(
        absl::StrCat("undock: the lift still carries a load ", timeout_s_, " s after lowering"));
  }
  return out;
}

}  // namespace fleetnav::agent
