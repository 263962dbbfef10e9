#include "fleetnav/robot_agent/control/modes/trolley_docking_controller.hpp"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/rate_limit.hpp"

namespace fleetnav::agent {

absl::Status TrolleyDockingParams::Validate() const {
  if (absl::Status s = spec.Validate(); !s.ok()) return s;
  for (double v : {max_range_m, search_timeout_s, expected_within_m, axis_within_rad, standoff_m,
                   approach_speed_mps, final_speed_mps, position_gain_per_s, yaw_gain_per_s,
                   approach_tolerance_m, final_tolerance_m, tolerance_rad, lift_timeout_s}) {
    if (!(v > 0.0) || !std::isfinite(v)) {
      return absl::InvalidArgumentError("trolley docking: parameters must be finite and > 0");
    }
  }
  if (median_window < 1) return absl::InvalidArgumentError("trolley docking: median_window >= 1");
  return absl::OkStatus();
}

TrolleyDockingController::TrolleyDockingController(const RobotModel& model,
                                                   TrolleyDockingParams params,
                                                   std::string target_id,
                                                   std::optional<Pose2> expected_in_map)
    : model_(model),
      params_(params),
      target_id_(std::move(target_id)),
      expected_in_map_(expected_in_map),
      median_(params.median_window) {}

namespace {

/// How far apart two trolley axes are, either way round (a trolley is symmetric): [0, π/2].
double AxisDifference(double a_rad, double b_rad) {
  const double d = std::abs(AngleDifference(a_rad, b_rad));
  return std::min(d, kPi - d);
}

}  // namespace

std::optional<Pose2> TrolleyDockingController::Measure(const ControlInput& input) {
  if (!input.perception.laser) return std::nullopt;
  const LaserScanSample scan = median_.Apply(*input.perception.laser);
  const std::vector<TrolleyDetection> trolleys = RecognizeTrolleys(
      LegCandidates(scan, input.perception.laser_in_base, params_.spec), params_.spec);
  // Where the site says the target stands, in the odometry frame.
  std::optional<Pose2> expected;
  if (expected_in_map_) {
    expected = input.pose_in_odom * input.pose_in_map.Inverse() * *expected_in_map_;
  }
  // Three legs and something else (a shelf's corner, another trolley's leg) can also make a
  // trolley's shape: the trolley being docked at, else the one the site expects, gates the
  // candidates by place and axis; four legs seen beat three; then the nearest to that reference
  // (or to the robot) wins.
  const std::optional<Pose2>& reference = trolley_in_odom_ ? trolley_in_odom_ : expected;
  const double within_m = trolley_in_odom_ ? 0.2 : params_.expected_within_m;
  std::optional<Pose2> best;
  int best_legs = 0;
  double best_distance_m = 0.0;
  for (const TrolleyDetection& t : trolleys) {
    if (t.pose_in_base.translation().norm() > params_.max_range_m) continue;
    const Pose2 seen = input.pose_in_odom * t.pose_in_base;
    double distance_m = t.pose_in_base.translation().norm();
    if (reference) {
      distance_m = (seen.translation() - reference->translation()).norm();
      if (distance_m > within_m ||
          AxisDifference(seen.yaw_rad(), reference->yaw_rad()) > params_.axis_within_rad) {
        continue;
      }
    }
    if (best &&
        (t.legs_seen < best_legs || (t.legs_seen == best_legs && distance_m >= best_distance_m))) {
      continue;
    }
    best = seen;
    best_legs = t.legs_seen;
    best_distance_m = distance_m;
  }
  if (best && trolley_in_odom_ &&
      std::abs(AngleDifference(best->yaw_rad(), trolley_in_odom_->yaw_rad())) > (kPi / 2)) {
    // Keep to the trolley's x axis as first found; it may be measured either way round.
    best = Pose2(best->x_m(), best->y_m(), best->yaw_rad() + kPi);
  }
  return best;
}

Twist2 TrolleyDockingController::DriveTo(const Pose2& target, const Pose2& pose, double speed_mps,
                                         double dt_s) {
  Eigen::Vector2d velocity =
      params_.position_gain_per_s * (target.translation() - pose.translation());
  if (velocity.norm() > speed_mps) velocity *= speed_mps / velocity.norm();
  const double yaw_rate =
      std::clamp(params_.yaw_gain_per_s * AngleDifference(target.yaw_rad(), pose.yaw_rad()),
                 -model_.limits.max_yaw_rate_radps, model_.limits.max_yaw_rate_radps);
  const double c = std::cos(pose.yaw_rad()), s = std::sin(pose.yaw_rad());
  const Twist2 wanted{c * velocity.x() + s * velocity.y(), -s * velocity.x() + c * velocity.y(),
                      yaw_rate};
  const double dv = model_.limits.max_accel_mps2 * dt_s;
  last_command_ = Twist2{StepTowards(last_command_.vx_mps, wanted.vx_mps, dv),
                         StepTowards(last_command_.vy_mps, wanted.vy_mps, dv),
                         StepTowards(last_command_.yaw_rate_radps, wanted.yaw_rate_radps,
                                     model_.limits.max_yaw_accel_radps2 * dt_s)};
  return last_command_;
}

ControlOutput TrolleyDockingController::Step(const ControlInput& input) {
  ControlOutput out;
  out.mode = NavigationMode::kDocking;
  const Pose2& pose = input.pose_in_odom;
  if (stage_ == Stage::kDone) {
    out.done = true;
    out.progress_fraction = 1.0;
    return out;
  }
  if (stage_ == Stage::kLift) {
    // Standing at the final frame with the lift raised until it reports the trolley on it.
    out.lift_raised = true;
    out.progress_fraction = 0.99;
    if (input.perception.lift_loaded) {
      stage_ = Stage::kDone;
      out.done = true;
      out.progress_fraction = 1.0;
      return out;
    }
    lifting_s_ += input.dt_s;
    if (lifting_s_ > params_.lift_timeout_s) {
      out.failure = absl::FailedPreconditionError(
          absl::StrCat("dock: the lift was raised under ",
                       target_id_.empty() ? std::string("the trolley")
                                          : absl::StrCat("trolley '", target_id_, "'"),
                       " but carries nothing after ", params_.lift_timeout_s, " s"));
    }
    return out;
  }
  const std::optional<Pose2> seen = Measure(input);
  if (stage_ == Stage::kSearch) {
    if (!seen) {
      searched_s_ += input.dt_s;
      if (searched_s_ > params_.search_timeout_s) {
        const std::string which = target_id_.empty()
                                      ? std::string("no trolley")
                                      : absl::StrCat("trolley '", target_id_, "' not");
        const std::string near = expected_in_map_ ? absl::StrCat(" near (", expected_in_map_->x_m(),
                                                                 ", ", expected_in_map_->y_m(), ")")
                                                  : std::string();
        out.failure = absl::NotFoundError(absl::StrCat(
            "dock: ", which, " in view within ", params_.max_range_m, " m", near, " (4 legs ",
            params_.spec.leg_spacing_x_m, " x ", params_.spec.leg_spacing_y_m, " m apart)"));
      }
      return out;  // standing still while looking
    }
    trolley_in_odom_ = seen;
    stage_ = Stage::kApproach;
    start_distance_m_ = (seen->translation() - pose.translation()).norm();
  } else if (seen) {
    // Each new measurement refines the estimate (the nearer, the better).
    const double w = stage_ == Stage::kFinal ? 0.1 : 0.3;
    const double yaw = trolley_in_odom_->yaw_rad() +
                       w * AngleDifference(seen->yaw_rad(), trolley_in_odom_->yaw_rad());
    const Eigen::Vector2d at = (1 - w) * trolley_in_odom_->translation() + w * seen->translation();
    trolley_in_odom_ = Pose2(at.x(), at.y(), yaw);
  }
  const DockFrames frames =
      DockFramesFor(*trolley_in_odom_, params_.spec, model_, params_.standoff_m);
  const double remaining = (frames.final.translation() - pose.translation()).norm();
  out.progress_fraction =
      start_distance_m_ > 0 ? std::clamp(1.0 - remaining / start_distance_m_, 0.0, 0.99) : 0.0;
  const bool slow = std::hypot(last_command_.vx_mps, last_command_.vy_mps) <
                    model_.limits.max_accel_mps2 * input.dt_s * 2;
  if (stage_ == Stage::kApproach) {
    const Pose2 to = frames.approach;
    if ((to.translation() - pose.translation()).norm() < params_.approach_tolerance_m &&
        std::abs(AngleDifference(to.yaw_rad(), pose.yaw_rad())) < params_.tolerance_rad && slow) {
      stage_ = Stage::kFinal;
    } else {
      out.command = DriveTo(to, pose, params_.approach_speed_mps, input.dt_s);
      return out;
    }
  }
  const Pose2 to = frames.final;
  if ((to.translation() - pose.translation()).norm() < params_.final_tolerance_m &&
      std::abs(AngleDifference(to.yaw_rad(), pose.yaw_rad())) < params_.tolerance_rad && slow) {
    stage_ = Stage::kLift;
    last_command_ = Twist2{};
    out.lift_raised = true;
    out.progress_fraction = 0.99;
    return out;
  }
  out.command = DriveTo(to, pose, params_.final_speed_mps, input.dt_s);
  return out;
}

}  // namespace fleetnav::agent
