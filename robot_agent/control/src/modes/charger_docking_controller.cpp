#include "fleetnav/robot_agent/control/modes/charger_docking_controller.hpp"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace fleetnav::agent {

absl::Status ChargerDockingParams::Validate() const {
  if (!(std::isfinite(approach_speed_mps) && approach_speed_mps > 0.0 &&
        std::isfinite(max_travel_m) && max_travel_m > 0.0)) {
    return absl::InvalidArgumentError("approach_speed_mps, max_travel_m: must be finite and > 0");
  }
  return absl::OkStatus();
}

ChargerDockingController::ChargerDockingController(std::vector<StripeMarker> charger_pieces,
                                                   MotionProfile profile,
                                                   StripeFollowingParams stripe,
                                                   ChargerDockingParams params)
    : params_(params),
      follower_(StripeNavigationAction{charger_pieces.empty() ? 0 : charger_pieces[0].stripe_id,
                                       params.max_travel_m, params.approach_speed_mps},
                EndConditionKind::kDistance, charger_pieces, profile, stripe,
                NavigationMode::kDocking, NavigationMode::kDocking) {}

ControlOutput ChargerDockingController::Step(const ControlInput& input) {
  ControlOutput out;
  out.mode = NavigationMode::kDocking;
  if (input.perception.charger_contact) {
    out.done = true;
    out.progress_fraction = 1.0;
    return out;
  }
  out = follower_.Step(input);
  out.mode = NavigationMode::kDocking;
  out.mode_reason.clear();
  if (out.done) {
    out.done = false;
    out.command = Twist2{};
    out.failure = absl::FailedPreconditionError(absl::StrFormat(
        "no charger contact within %.1f m of charger stripe", params_.max_travel_m));
  } else if (!out.failure.ok()) {
    out.failure =
        absl::FailedPreconditionError(absl::StrCat("charger stripe lost: ", out.failure.message()));
  }
  return out;
}

}  // namespace fleetnav::agent
