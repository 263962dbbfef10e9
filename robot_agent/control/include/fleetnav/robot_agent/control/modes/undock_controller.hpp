#pragma once

#include "absl/status/status.h"
#include "fleetnav/robot_agent/control/common/motion_controller.hpp"

namespace fleetnav::agent {

/// The undock action (KUKA thesis ch. 15, the reverse of the final dock frame): standing still,
/// the platform lowers its lift and the trolley it carried stands on its own casters again. Done
/// when the lift no longer reports a load; fails (FailedPrecondition) when it still does after
/// `timeout_s`. The robot stays under the trolley: a following move drives out. Not
/// thread-safe.
class UndockController : public MotionController {
 public:
  explicit UndockController(double timeout_s = 2.0) : timeout_s_(timeout_s) {}
  ControlOutput Step(const ControlInput& input) override;

 private:
  double timeout_s_;
  double lowering_s_ = 0.0;
};

}  // namespace fleetnav::agent
