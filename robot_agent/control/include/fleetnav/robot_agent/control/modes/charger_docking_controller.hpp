#pragma once

#include <optional>
#include <vector>

#include "fleetnav/core/stripe_marker.hpp"
#include "fleetnav/robot_agent/control/common/motion_controller.hpp"
#include "fleetnav/robot_agent/control/modes/stripe_following_controller.hpp"

namespace fleetnav::agent {

struct ChargerDockingParams {
  /// Slow enough to stop inside the charger contact's travel (5 cm at 0.3 m/s² takes 0.17 m/s).
  double approach_speed_mps = 0.1;
  /// Give up when the contact has not closed after this much travel on the charger stripe.
  double max_travel_m = 8.0;
  absl::Status Validate() const;
};

/// Charger docking (Lely thesis §6.6): follow the charger stripe slowly until the charger
/// contact closes, then stop and report it; the stripe ending or the travel running out without
/// contact fails the action with the reason. Not thread-safe.
class ChargerDockingController : public MotionController {
 public:
  ChargerDockingController(std::vector<StripeMarker> charger_pieces, MotionProfile profile,
                           StripeFollowingParams stripe = {}, ChargerDockingParams params = {});
  ControlOutput Step(const ControlInput& input) override;

 private:
  ChargerDockingParams params_;
  StripeFollowingController follower_;
};

}  // namespace fleetnav::agent
