#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/core/stripe_marker.hpp"
#include "fleetnav/robot_agent/control/common/motion_controller.hpp"
#include "fleetnav/robot_agent/control/modes/charger_docking_controller.hpp"
#include "fleetnav/robot_agent/control/modes/fence_following_controller.hpp"
#include "fleetnav/robot_agent/control/modes/free_navigation_controller.hpp"
#include "fleetnav/robot_agent/control/modes/motion_controllers.hpp"
#include "fleetnav/robot_agent/control/modes/move_controller.hpp"
#include "fleetnav/robot_agent/control/modes/trolley_docking_controller.hpp"
#include "fleetnav/robot_agent/control/modes/undock_controller.hpp"

namespace fleetnav::agent {

/// How the executor's controllers are tuned for one robot.
struct ModeParams {
  MotionProfile profile;
  HeadingPidGains heading;
  FenceFollowingParams fence;
  StripeFollowingParams stripe;
  ChargerDockingParams docking;
  FreeNavigationParams free_navigation;
  MoveParams move;
  TrolleyDockingParams trolley_docking;
  absl::Status Validate() const;
};

/// What the robot brings to a route: its model and, when it has them, the marker set of the
/// route's map (marker end conditions, the stripes' geometry) and the map itself (free
/// navigation), and the trolley on its lift when it carries one.
struct RouteContext {
  RobotModel model;
  std::optional<MarkerSet> markers;
  std::shared_ptr<const OccupancyGrid> map;
  /// The outer size (length, width) of the trolley latched on the robot's lift; nullopt when
  /// it carries none.
  std::optional<Eigen::Vector2d> carried_load_m;
  /// The trolleys this robot moved on `map`: free navigation plans with them where they are.
  MovedLoads moved_loads;
  /// The robot as the planner and the tracker must see it: grown to the trolley it carries.
  RobotModel NavigationModel() const {
    return carried_load_m ? model.CarryingLoad(*carried_load_m) : model;
  }
};

/// What the robot carries after `action` completes, given what it carried before it
/// (`context.carried_load_m`): a trolley dock latches the trolley (its size from the marker
/// set's placement, else the docking spec's legs), an undock sets it down.
std::optional<Eigen::Vector2d> LoadAfter(const RouteAction& action, const RouteContext& context,
                                         const ModeParams& params);

/// The action types this agent version executes on a robot of `model`, as advertised to
/// fleetnavd: turning in place needs a drive that can (not Ackermann), fence following a side
/// ultrasonic, stripes and docking inductive sensors.
std::vector<std::string> SupportedActionTypes(const RobotModel& model);

/// Checks a whole route before the robot moves: every action type and end condition is
/// executable here, its sensors are fitted, and every marker it ends on is in the marker set.
/// FailedPrecondition naming the action's index and what is missing.
absl::Status CheckRoute(const Route& route, const RouteContext& context,
                        const ModeParams& params = {});

/// The controller of one action (the mode of Fig. 6.12), or FailedPrecondition naming the index.
/// `previous` is the action before it in the route, if any (a move continues from the
/// direction the one before it travelled in).
absl::StatusOr<std::unique_ptr<MotionController>> MakeController(
    const RouteAction& action, int index, const RouteContext& context, const ModeParams& params,
    const RouteAction* previous = nullptr);

}  // namespace fleetnav::agent
