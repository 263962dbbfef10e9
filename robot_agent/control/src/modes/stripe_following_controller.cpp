#include "fleetnav/robot_agent/control/modes/stripe_following_controller.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace fleetnav::agent {
namespace {

constexpr double kDistanceToleranceM = 0.002;
constexpr double kSharedEndM = 0.02;  ///< piece ends closer than this join two pieces

Eigen::Vector2d PieceEnd(const StripeMarker& piece, double sign) {
  return piece.position_m + sign * 0.5 * piece.length_m *
                                Eigen::Vector2d(std::cos(piece.yaw_rad), std::sin(piece.yaw_rad));
}

}  // namespace

absl::Status StripeFollowingParams::Validate() const {
  for (double v : {gain_radps_per_m, max_yaw_rate_radps, line_memory_m, end_tolerance_m,
                   unknown_end_after_m, max_interruption_m, search_m, curve_lookahead_m,
                   straight_curvature_per_m, straight_heading_rad}) {
    if (!(std::isfinite(v) && v > 0.0)) {
      return absl::InvalidArgumentError("stripe following parameters: must be finite and > 0");
    }
  }
  if (lost_after_ticks < 1 || found_after_ticks < 1) {
    return absl::InvalidArgumentError("lost_after_ticks, found_after_ticks: must be >= 1");
  }
  if (!(curve_yaw_share > 0.0 && curve_yaw_share <= 1.0)) {
    return absl::InvalidArgumentError("curve_yaw_share: must be in (0, 1]");
  }
  return absl::OkStatus();
}

StripeFollowingController::StripeFollowingController(
    const StripeNavigationAction& action, EndConditionKind end,
    std::vector<StripeMarker> stripe_pieces, MotionProfile profile, StripeFollowingParams params,
    NavigationMode reactive_mode, NavigationMode map_based_mode)
    : action_(action),
      end_(end),
      pieces_(std::move(stripe_pieces)),
      profile_(profile),
      params_(params),
      reactive_mode_(reactive_mode),
      map_based_mode_(map_based_mode),
      line_(params.line_memory_m) {
  path_ = StripePath::Build(pieces_, action_.stripe_id);
  if (path_) {
    ends_ = {path_->front(), path_->back()};
    return;
  }
  // No chain: the pieces of the action's stripe, or all of them when none is named.
  std::vector<StripeMarker> own;
  for (const StripeMarker& piece : pieces_) {
    if (piece.stripe_id == action_.stripe_id) own.push_back(piece);
  }
  if (!own.empty()) pieces_ = std::move(own);
  // The stripe's ends: piece ends that no other piece of the stripe shares.
  for (size_t i = 0; i < pieces_.size(); ++i) {
    for (double sign : {-1.0, 1.0}) {
      const Eigen::Vector2d end_point = PieceEnd(pieces_[i], sign);
      bool shared = false;
      for (size_t j = 0; j < pieces_.size() && !shared; ++j) {
        if (j == i) continue;
        shared = (PieceEnd(pieces_[j], -1.0) - end_point).norm() < kSharedEndM ||
                 (PieceEnd(pieces_[j], 1.0) - end_point).norm() < kSharedEndM;
      }
      if (!shared) ends_.push_back(end_point);
    }
  }
}

double StripeFollowingController::DistanceToStripeEnd(const Eigen::Vector2d& point) const {
  double best = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector2d& end : ends_) best = std::min(best, (end - point).norm());
  if (foot_) {
    // Past an end (the sensor's foot this tick is an end): the stripe has ended, however far
    // the estimate ran on.
    return foot_->s_m <= kDistanceToleranceM ||
                   foot_->s_m >= path_->length_m() - kDistanceToleranceM
               ? 0.0
               : best;
  }
  // Past an end (the nearest point of the stripe is that end): the stripe has ended, however far
  // the estimate has run on (wheel slip makes odometry run ahead).
  double nearest = std::numeric_limits<double>::infinity();
  Eigen::Vector2d nearest_point = point;
  for (const StripeMarker& piece : pieces_) {
    const Line2 line = piece.AsLine();
    const double along = std::clamp((point - line.point).dot(line.direction), -0.5 * piece.length_m,
                                    0.5 * piece.length_m);
    const Eigen::Vector2d on = line.point + along * line.direction;
    if ((on - point).norm() < nearest) {
      nearest = (on - point).norm();
      nearest_point = on;
    }
  }
  for (const Eigen::Vector2d& end : ends_) {
    if ((end - nearest_point).norm() < kSharedEndM) return 0.0;
  }
  return best;
}

void StripeFollowingController::FallbackLine(const Eigen::Vector2d& point, Eigen::Vector2d* on_line,
                                             Eigen::Vector2d* direction) const {
  if (foot_) {
    *on_line = foot_->point;
    *direction = foot_->tangent;
    return;
  }
  double best = std::numeric_limits<double>::infinity();
  for (const StripeMarker& piece : pieces_) {
    const Line2 line = piece.AsLine();
    const double along = std::clamp((point - line.point).dot(line.direction), -0.5 * piece.length_m,
                                    0.5 * piece.length_m);
    const double distance = (line.point + along * line.direction - point).norm();
    if (distance < best) {
      best = distance;
      *on_line = line.point;
      *direction = line.direction;
    }
  }
  if (pieces_.empty()) {
    *on_line = line_.point();
    *direction = line_.direction();
  }
}

ControlOutput StripeFollowingController::Step(const ControlInput& input) {
  const Pose2 sensor_in_map =
      input.pose_in_map * Pose2(input.perception.stripe_sensor_x_m, 0.0, 0.0);
  const Eigen::Vector2d heading(std::cos(input.pose_in_map.yaw_rad()),
                                std::sin(input.pose_in_map.yaw_rad()));
  if (!started_) {
    started_ = true;
    last_odom_ = input.pose_in_odom;
    line_.Assume(sensor_in_map.translation(), heading);
    if (path_) path_->OrientAlong(sensor_in_map.translation(), heading);
  }
  if (path_) foot_ = path_->Project(sensor_in_map.translation());
  const Pose2 moved = Between(last_odom_, input.pose_in_odom);
  const double step_m = std::hypot(moved.x_m(), moved.y_m());
  travelled_m_ += step_m;
  last_odom_ = input.pose_in_odom;

  ControlOutput out;
  const bool limited = action_.distance_m > 0.0 && end_ == EndConditionKind::kDistance;
  const double remaining_m =
      limited ? action_.distance_m - travelled_m_ : std::numeric_limits<double>::infinity();
  out.progress_fraction = limited ? std::clamp(travelled_m_ / action_.distance_m, 0.0, 1.0) : 0.0;
  if (remaining_m <= kDistanceToleranceM) {
    out.done = true;
    out.progress_fraction = 1.0;
    return out;
  }

  const std::optional<double>& offset = input.perception.stripe_offset_m;
  if (offset) {
    seen_ = true;
    ++present_ticks_;
    missing_ticks_ = 0;
    lost_since_m_ = 0.0;
    line_.Add(
        (input.pose_in_map * Pose2(input.perception.stripe_sensor_x_m, *offset, 0.0)).translation(),
        travelled_m_, heading);
  } else {
    ++missing_ticks_;
    present_ticks_ = 0;
    lost_since_m_ += step_m;
  }
  if (!seen_ && travelled_m_ > params_.search_m) {
    out.failure = absl::FailedPreconditionError(
        absl::StrFormat("no stripe under the inductive sensors after %.2f m", travelled_m_));
    return out;
  }
  if (seen_ && missing_ticks_ >= params_.lost_after_ticks) {
    // Lost: the stripe's end, or an interruption?
    const bool at_end = pieces_.empty() ? lost_since_m_ >= params_.unknown_end_after_m
                                        : DistanceToStripeEnd(sensor_in_map.translation()) <=
                                              params_.end_tolerance_m;
    if (at_end) {
      if (end_ == EndConditionKind::kStripeEnd || !limited) {
        out.done = true;
        out.progress_fraction = 1.0;
        return out;
      }
      out.failure = absl::FailedPreconditionError(
          absl::StrFormat("stripe %d ended after %.2f m, before the action's %.2f m",
                          action_.stripe_id, travelled_m_, action_.distance_m));
      return out;
    }
    if (lost_since_m_ > params_.max_interruption_m) {
      out.failure = absl::FailedPreconditionError(absl::StrFormat(
          "stripe %d lost for %.1f m, away from its ends", action_.stripe_id, lost_since_m_));
      return out;
    }
    if (!map_based_) {
      map_based_ = true;
      out.mode_reason = absl::StrCat("stripe ", action_.stripe_id, " interrupted: no reading for ",
                                     missing_ticks_, " ticks");
    }
  } else if (map_based_ && present_ticks_ >= params_.found_after_ticks) {
    map_based_ = false;
    out.mode_reason = absl::StrCat("stripe ", action_.stripe_id, " answers again");
  }
  out.mode = map_based_ ? map_based_mode_ : reactive_mode_;

  double error_m = 0.0;  // where the stripe is, left of the sensors
  if (offset && !map_based_) {
    error_m = *offset;
  } else {
    Eigen::Vector2d on_line, direction;
    FallbackLine(sensor_in_map.translation(), &on_line, &direction);
    if (direction.dot(heading) < 0.0) direction = -direction;
    const Eigen::Vector2d normal(-direction.y(), direction.x());
    error_m = -(sensor_in_map.translation() - on_line).dot(normal);
  }
  // The sensor's speed along the stripe, slowed for the sharpest curve just ahead.
  double target_mps = action_.speed_mps;
  if (foot_) {
    const double ahead = path_->MaxCurvatureAhead(foot_->s_m, params_.curve_lookahead_m);
    if (ahead > 1e-6) {
      target_mps =
          std::min(target_mps, params_.curve_yaw_share * params_.max_yaw_rate_radps / ahead);
    }
  }
  const double sensor_mps =
      profile_.NextSpeed(target_mps, last_speed_mps_, remaining_m, input.dt_s);
  last_speed_mps_ = sensor_mps;
  const double lead_m = input.perception.stripe_sensor_x_m;
  double speed = sensor_mps;
  double yaw_rate = params_.gain_radps_per_m * error_m;
  if (foot_ && lead_m > 1e-3) {
    // Near a curve, or still turned from one, the sensor point is steered along the known
    // stripe (feedback linearization of the point L ahead of the axle): its velocity is the
    // stripe's tangent at the sensor's speed plus the lateral correction, which the robot
    // produces with v = ṡ·h and ω = ṡ·h⊥ / L. On straight stripes the P law alone, which needs
    // no estimated heading.
    const Eigen::Vector2d& tangent = foot_->tangent;
    const Eigen::Vector2d left(-heading.y(), heading.x());
    const bool turned = tangent.dot(heading) < std::cos(params_.straight_heading_rad);
    const bool near_curve =
        path_->MaxCurvatureAhead(foot_->s_m - lead_m, lead_m + params_.curve_lookahead_m) >
        params_.straight_curvature_per_m;
    if (turned || near_curve) {
      const Eigen::Vector2d normal(-tangent.y(), tangent.x());
      const Eigen::Vector2d sensor_velocity =
          sensor_mps * tangent + params_.gain_radps_per_m * lead_m * error_m * normal;
      speed = std::max(0.0, sensor_velocity.dot(heading));
      yaw_rate = sensor_velocity.dot(left) / lead_m;
      if (std::abs(yaw_rate) > params_.max_yaw_rate_radps) {
        speed *= params_.max_yaw_rate_radps / std::abs(yaw_rate);
      }
    }
  }
  yaw_rate = std::clamp(yaw_rate, -params_.max_yaw_rate_radps, params_.max_yaw_rate_radps);
  out.command = Twist2{speed, 0.0, yaw_rate};
  return out;
}

}  // namespace fleetnav::agent
