#include "fleetnav/robot_agent/move_controller.hpp"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "fleetnav/planner/trajectory/spline.hpp"

namespace fleetnav::agent {

absl::Status MoveParams::Validate() const {
  if (!(augment_radius_m > 0.0) || !std::isfinite(augment_radius_m)) {
    return absl::InvalidArgumentError("move.augment_radius_m: must be finite and > 0");
  }
  if (!(augment_max_turn_rad > 0.0 && augment_max_turn_rad <= M_PI)) {
    return absl::InvalidArgumentError("move.augment_max_turn_rad: must be in (0, pi]");
  }
  if (!(sample_spacing_m > 0.0) || !std::isfinite(sample_spacing_m)) {
    return absl::InvalidArgumentError("move.sample_spacing_m: must be finite and > 0");
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
                               const RobotModel& model, MoveParams params)
    : move_(move),
      entry_direction_(entry_direction),
      params_(params),
      tracker_(TrackerFor(move, params.tracker), model.limits) {}

absl::Status MoveController::Plan(const Pose2& start) {
  const double yaw = start.yaw_rad();
  const Eigen::Vector2d from = start.translation();
  const Eigen::Vector2d to = start.TransformPoint({move_.dx_m, move_.dy_m});
  const Eigen::Vector2d direction = (to - from).normalized();
  std::vector<Eigen::Vector2d> points;
  if (params_.augment_endpoints && entry_direction_ && entry_direction_->norm() > 1e-9) {
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
  if (points.empty()) {
    const double length = (to - from).norm();
    const int n = std::max(1, static_cast<int>(std::ceil(length / params_.sample_spacing_m)));
    for (int i = 0; i <= n; ++i) points.push_back(from + (to - from) * (double(i) / n));
  }
  path_.clear();
  length_m_ = 0.0;
  for (size_t i = 0; i < points.size(); ++i) {
    if (i > 0) length_m_ += (points[i] - points[i - 1]).norm();
    path_.emplace_back(points[i].x(), points[i].y(), yaw);
  }
  tracker_.SetPath(path_);
  return absl::OkStatus();
}

ControlOutput MoveController::Step(const ControlInput& input) {
  ControlOutput out;
  out.mode = NavigationMode::kFreeNavigation;
  if (!planned_) {
    planned_ = true;
    if (absl::Status s = Plan(input.pose_in_map); !s.ok()) {
      out.failure = absl::InternalError(absl::StrCat("move: no path: ", s.message()));
      return out;
    }
  }
  out.command = tracker_.Step(input.pose_in_map, input.dt_s);
  out.done = tracker_.done();
  out.progress_fraction =
      length_m_ > 0.0 ? std::clamp(1.0 - tracker_.remaining_m() / length_m_, 0.0, 1.0) : 1.0;
  if (out.done) {
    out.command = Twist2{};
    out.progress_fraction = 1.0;
  }
  return out;
}

}  // namespace fleetnav::agent
