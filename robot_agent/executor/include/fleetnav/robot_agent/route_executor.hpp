#pragma once

#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "fleetnav/core/job_assignment.hpp"
#include "fleetnav/core/route.hpp"
#include "fleetnav/core/segment_gate.hpp"
#include "fleetnav/robot_agent/control/common/motion_controller.hpp"
#include "fleetnav/robot_agent/mode_factory.hpp"

namespace fleetnav::agent {

enum class ExecutionState { kRunning, kSucceeded, kFailed };

/// What the executor asks of the drive this tick, and where it stands.
struct ExecutorOutput {
  Twist2 command;
  NavigationMode mode = NavigationMode::kIdle;
  int action_index = -1;
  double progress_fraction = 0.0;  ///< of the whole route
  double action_fraction = 0.0;    ///< of action action_index
  ExecutionState state = ExecutionState::kRunning;
  /// Set on the tick the mode switched between reactive and map-based: why.
  std::string mode_reason;
  /// Action action_index is done (or none has started) and the next one is not cleared by
  /// traffic coordination: the robot stands.
  bool waiting = false;
  /// Where the lift must be, and the trolley on it (nullopt: none): a trolley dock latches one,
  /// an undock sets it down, and it stays on the lift when a route ends or fails.
  bool lift_raised = false;
  std::optional<Eigen::Vector2d> carried_load_m;
};

/// Runs a route's actions one after another (Lely thesis §6.3): each action gets its
/// MotionController from the mode factory when it starts and hands over when its end
/// condition holds — its own distance or angle, or a calibration marker that the localizer
/// detected (never the simulator's truth). The whole route is checked before the first tick
/// moves the robot: an action this agent cannot run fails the route at once, naming its index,
/// and so does, given the pose the robot starts at, an action the site does not allow
/// (CheckRouteOnSite: a fence leg with no fence near, an unreachable goal), so nothing is
/// half-executed. Abort() stops it (safety stop). Traffic coordination gates it:
/// an action starts only when its index is at most SetClearedUpTo's (no gate by default); until
/// then the robot stands and Step reports `waiting`. Not thread-safe.
class RouteExecutor {
 public:
  /// `from`: where to begin instead of the route's beginning (an agent restarted in the middle
  /// of a job): the action there runs only what is left of it (RemainderOf, given the robot at
  /// start_in_map), its progress counts from what was done, and the site check starts there.
  RouteExecutor(Route route, RouteContext context, ModeParams params = {},
                std::optional<Pose2> start_in_map = std::nullopt, const RoutePosition& from = {});

  /// One control tick. `detected_markers` are the calibration markers the localizer associated
  /// with an inductive edge this tick.
  ExecutorOutput Step(const ControlInput& input, const std::vector<int>& detected_markers = {});
  /// Fails the current action with `reason` (prefixed with its index); the robot is told to stop.
  void Abort(const absl::Status& reason);
  /// Actions up to `index` may start (-1: none).
  void SetClearedUpTo(int index) { cleared_up_to_ = index; }
  /// Within action hold->action_index, the robot may go only up to the hold's gate: it brakes
  /// to stand just before it, in the order of its own path where it follows one (nullopt: the
  /// whole of every cleared action). Once it stands there it stays until told another hold.
  void SetHold(const std::optional<SegmentHold>& hold);
  /// Drives free-navigation action path.action_index through the path's waypoints to its goal
  /// (a path traffic coordination planned around robots that stand). An action not begun
  /// takes it when it starts; the action under way plans again from where the robot is, its
  /// progress going on from what was done. A path already taken (same id), one for an action
  /// that has ended, or one for an action that is not free navigation is ignored.
  void SetActionPath(const ActionPath& path);
  ExecutionState state() const { return state_; }
  /// Why the route failed (OK while running or after success).
  const absl::Status& failure() const { return failure_; }
  const Route& route() const { return route_; }
  int action_index() const { return index_; }
  /// The trolleys moved on the map, those the route started with and those it moved since.
  const MovedLoads& moved_loads() const { return context_.moved_loads; }
  /// The trolley on the lift now (its outer size); nullopt when none.
  const std::optional<Eigen::Vector2d>& carried_load_m() const { return context_.carried_load_m; }
  /// The map the actions started from now on plan on (zones put while the route runs: their
  /// no-go zones occupied); the action under way keeps its own.
  void SetNavigationMap(std::shared_ptr<const OccupancyGrid> map) { context_.map = std::move(map); }
  /// How many times an action's controller was made: it grows as an action starts or starts
  /// again (a new path for it).
  int actions_started() const { return actions_started_; }

 private:
  /// Moves the start to `position` (see the constructor).
  absl::Status ResumeAt(const RoutePosition& position, const Pose2& pose_in_map);
  absl::Status StartAction(int index);
  ExecutorOutput StepActions(const ControlInput& input, const std::vector<int>& detected_markers);
  ExecutorOutput Fail(absl::Status status);
  ExecutorOutput Waiting() const;
  /// Slows `out`'s command so that the robot stands before hold_'s gate.
  void HoldBeforeGate(const ControlInput& input, ExecutorOutput* out);
  /// The progress of action index_ given its controller's, counted from the resumed fraction.
  double ActionFraction(double controller_fraction) const;

  Route route_;
  RouteContext context_;
  ModeParams params_;
  int index_ = -1;
  int actions_started_ = 0;
  int cleared_up_to_ = std::numeric_limits<int>::max();
  bool waiting_ = false;         ///< action index_ is done; index_ + 1 is not cleared yet
  int resumed_index_ = -1;       ///< the action ResumeAt began in the middle of
  double resumed_fraction_ = 0;  ///< how much of it was done before
  std::unique_ptr<MotionController> controller_;
  ExecutionState state_ = ExecutionState::kRunning;
  absl::Status failure_;
  bool lift_raised_ = false;
  std::optional<SegmentHold> hold_;
  /// The robot has come to hold_'s gate along its path: it stands, wherever its path turns.
  bool stands_at_gate_ = false;
  double action_fraction_ = 0.0;           ///< of action index_, as last reported
  std::map<int, uint64_t> taken_path_id_;  ///< per action: the planned path it drives
};

}  // namespace fleetnav::agent
