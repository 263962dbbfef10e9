#pragma once

#include <cmath>

#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_state.hpp"

namespace fleetnav::agent::testing {

/// A perfect unicycle for controller tests: integrates a commanded body twist exactly (arcs of
/// constant v and ω) and keeps the heading unwrapped so that turns beyond ±π stay visible.
class KinematicUnicycle {
 public:
  explicit KinematicUnicycle(const Pose2& start = Pose2())
      : x_m_(start.x_m()), y_m_(start.y_m()), yaw_rad_(start.yaw_rad()) {}

  void Step(const Twist2& twist, double dt_s) {
    const double v = twist.vx_mps;
    const double w = twist.yaw_rate_radps;
    if (std::abs(w) < 1e-12) {
      x_m_ += v * dt_s * std::cos(yaw_rad_);
      y_m_ += v * dt_s * std::sin(yaw_rad_);
    } else {
      x_m_ += v / w * (std::sin(yaw_rad_ + w * dt_s) - std::sin(yaw_rad_));
      y_m_ += -v / w * (std::cos(yaw_rad_ + w * dt_s) - std::cos(yaw_rad_));
    }
    yaw_rad_ += w * dt_s;
  }

  Pose2 pose() const { return Pose2(x_m_, y_m_, yaw_rad_); }
  double unwrapped_yaw_rad() const { return yaw_rad_; }

 private:
  double x_m_;
  double y_m_;
  double yaw_rad_;
};

/// An ideal omnidirectional body for controller tests: `pose` moved by a body twist held for
/// `dt_s` (Euler step at the start's yaw).
inline Pose2 MovedOmni(const Pose2& pose, const Twist2& v, double dt_s) {
  const double c = std::cos(pose.yaw_rad()), s = std::sin(pose.yaw_rad());
  return Pose2(pose.x_m() + (c * v.vx_mps - s * v.vy_mps) * dt_s,
               pose.y_m() + (s * v.vx_mps + c * v.vy_mps) * dt_s,
               pose.yaw_rad() + v.yaw_rate_radps * dt_s);
}

}  // namespace fleetnav::agent::testing
