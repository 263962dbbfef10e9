#pragma once

#include <numbers>

namespace fleetnav {

inline constexpr double kPi = std::numbers::pi;

/// Wraps an angle to (-pi, pi].
double NormalizeAngle(double angle_rad);

/// Smallest signed difference a - b, wrapped to (-pi, pi].
double AngleDifference(double a_rad, double b_rad);

constexpr double DegToRad(double deg) { return deg * kPi / 180.0; }
constexpr double RadToDeg(double rad) { return rad * 180.0 / kPi; }

}  // namespace fleetnav
