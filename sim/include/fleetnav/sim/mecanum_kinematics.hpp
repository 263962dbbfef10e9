#pragma once

#include <array>

#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/robot_state.hpp"

namespace fleetnav::sim {

/// Wheel angular velocities of a mecanum platform, front-left, front-right, rear-left,
/// rear-right (rad/s, forward rolling positive).
using MecanumWheelRates = std::array<double, 4>;

/// Mecanum inverse kinematics (KUKA thesis eq. 4.5–4.8 with T_X = wheelbase/2, T_Y = track/2,
/// rollers at 45°): the wheel rates that produce a body twist.
MecanumWheelRates MecanumInverse(const RobotModel& model, const Twist2& twist);
/// Mecanum forward kinematics (the thesis's pseudo-inverse, eq. 4.15–4.17).
Twist2 MecanumForward(const RobotModel& model, const MecanumWheelRates& rates);

/// An omnidirectional twist times `scale`, each component clamped to the model's limits.
Twist2 ClampOmniTwist(const MotionLimits& limits, const Twist2& twist, double scale);

}  // namespace fleetnav::sim
