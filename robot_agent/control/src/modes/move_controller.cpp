#include "fleetnav/robot_agent/control/modes/move_controller.hpp"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/planner/trajectory/spline.hpp"

namespace fleetnav::agent {

absl::Status MoveParams::Validate() const {
  if (!(augment_radius_m > 0.0) || !std::isfinite(augment_radius_m)) {
    return absl::InvalidArgumentError("move.augment_radius_m: must be finite and > 0");
  }
  if (!(augment_max_turn_rad > 0.0 && augment_max_turn_rad <= kPi)) {
    return absl::InvalidArgumentError("move.augment_max_turn_rad: must be in (0, pi]");
  }
  if (!(sample_spacing_m > 0.0) || !std::isfinite(sample_spacing_m)) {
    return absl::InvalidArgumentError("move.sample_spacing_m: must be finite and > 0");
  }
  if (!(gate_max_offset_m >= 0.0) || !std::isfinite(gate_max_offset_m)) {
    return absl::InvalidArgumentError("move.gate_max_offset_m: must be finite and >= 0");
  }
  if (!(gate_max_angle_rad >= 0.0 && gate_max_angle_rad <= kPi / 2)) {
    return absl::InvalidArgumentError("move.gate_max_angle_rad: must be in [0, pi/2]");
  }
  if (gate_scans < 1) return absl::InvalidArgumentError("move.gate_scans: must be >= 1");
  if (!(gate_wait_s >= 0.0) || !std::isfinite(gate_wait_s)) {
    return absl::InvalidArgumentError("move.gate_wait_s: must be finite and >= 0");
  }
  return tracker.Validate();
}

namespace {

HolonomicTrackerParams TrackerFor(const MoveAction& move, HolonomicTrackerParams tracker) {
  tracker.desired_speed_mps = move.speed_mps;
  return tracker;
}

}  // namespace

MoveController::MoveController(const MoveAction& move,
                               std::optional<Eigen::Vector2d> entry_direction,
                               const RobotModel& model, MoveParams params,
                               std::optional<TrolleySpec> leaving_trolley)
    : move_(move),
      entry_direction_(entry_direction),
      params_(params),
      tracker_(TrackerFor(move, params.tracker), model.limits),
      leaving_trolley_(leaving_trolley),
      median_(params.gate_scans) {}

std::optional<LegGate> MoveController::Gate(const Pose2& laser_in_base) const {
  if (!leaving_trolley_ || !filtered_scan_) return std::nullopt;
  const Eigen::Vector2d move(move_.dx_m, move_.dy_m);
  if (move.norm() < 1e-9) return std::nullopt;
  return FindLegGate(LegsAround(*filtered_scan_, laser_in_base, *leaving_trolley_),
                     move.normalized(), *leaving_trolley_, params_.gate_max_offset_m,
                     params_.gate_max_angle_rad);
}

absl::Status MoveController::Plan(const Pose2& start, const std::optional<LegGate>& gate) {
  double yaw = start.yaw_rad();
  Eigen::Vector2d from = start.translation();
  Eigen::Vector2d to = start.TransformPoint({move_.dx_m, move_.dy_m});
  std::vector<Eigen::Vector2d> points;
  if (gate) {
    // Onto the gate's centre line level with where the robot stands, square to the legs, then
    // out along it for the move's length.
    const Eigen::Vector2d middle = start.TransformPoint(gate->middle_m);
    const Eigen::Vector2d out = Pose2(0.0, 0.0, yaw).TransformPoint(gate->direction);
    const Eigen::Vector2d move_in_base(move_.dx_m, move_.dy_m);
    yaw += std::atan2(gate->direction.y(), gate->direction.x()) -
           std::atan2(move_in_base.y(), move_in_base.x());
    const Eigen::Vector2d on_line = middle + out * (from - middle).dot(out);
    to = on_line + out * move_in_base.norm();
    points.push_back(from);
    from = on_line;
  }
  const Eigen::Vector2d direction = (to - from).normalized();
  if (!gate && params_.augment_endpoints && entry_direction_ && entry_direction_->norm() > 1e-9) {
    const Eigen::Vector2d entry = Pose2(0, 0, yaw).TransformPoint(entry_direction_->normalized());
    const std::vector<Eigen::Vector2d> knots = planner::AugmentEndpoints(
        {from - entry, from, to}, params_.augment_radius_m, params_.augment_max_turn_rad);
    if (knots.size() == 4) {  // the move turns back: bend round through the augmented knot
      absl::StatusOr<planner::CubicSpline> spline =
          planner::CubicSpline::Create({from, knots[2], to}, entry, direction);
      if (!spline.ok()) return spline.status();
      points = spline->Sample(1.0 / params_.sample_spacing_m);
    }
  }
  const bool straight = points.size() <= 1;  // empty, or the start before a gate's line
  if (straight) {
    const double length = (to - from).norm();
    const int n = std::max(1, static_cast<int>(std::ceil(length / params_.sample_spacing_m)));
    for (int i = 0; i <= n; ++i) points.push_back(from + (to - from) * (double(i) / n));
  }
  path_.clear();
  length_m_ = 0.0;
  for (size_t i = 0; i < points.size(); ++i) {
    if (i > 0) length_m_ += (points[i] - points[i - 1]).norm();
    // Through a gate the robot squares up to the legs from its first step on.
    path_.emplace_back(points[i].x(), points[i].y(), gate && i == 0 ? start.yaw_rad() : yaw);
  }
  tracker_.SetPath(path_);
  return absl::OkStatus();
}

ControlOutput MoveController::Step(const ControlInput& input) {
  ControlOutput out;
  out.mode = NavigationMode::kFreeNavigation;
  if (!planned_) {
    // Leaving from under a trolley: stand for a few scans of its legs (median-filtered).
    if (leaving_trolley_ && scans_ < params_.gate_scans && waited_s_ < params_.gate_wait_s) {
      waited_s_ += input.dt_s;
      if (input.perception.laser) {
        filtered_scan_ = median_.Apply(*input.perception.laser);
        ++scans_;
      }
      if (scans_ < params_.gate_scans) return out;
    }
    planned_ = true;
    if (absl::Status s = Plan(input.pose_in_map, Gate(input.perception.laser_in_base)); !s.ok()) {
      out.failure = absl::InternalError(absl::StrCat("move: no path: ", s.message()));
      return out;
    }
  }
  out.command = tracker_.Step(input.pose_in_map, input.dt_s);
  out.done = tracker_.done();
  // The tracker's remaining length jitters by up to a path sample between samples; progress
  // reported to the fleet only grows.
  progress_fraction_ = std::max(
      progress_fraction_,
      length_m_ > 0.0 ? std::clamp(1.0 - tracker_.remaining_m() / length_m_, 0.0, 1.0) : 1.0);
  out.progress_fraction = progress_fraction_;
  if (out.done) {
    out.command = Twist2{};
    out.progress_fraction = 1.0;
  }
  return out;
}

}  // namespace fleetnav::agent
