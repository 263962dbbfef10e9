#include "fleetnav/core/angles.hpp"

#include <cmath>

namespace fleetnav {

double NormalizeAngle(double angle_rad) {
  if (!std::isfinite(angle_rad)) return angle_rad;
  // std::remainder yields a value in [-pi, pi]; the closed lower end is moved to +pi.
  double wrapped = std::remainder(angle_rad, 2.0 * kPi);
  if (wrapped <= -kPi) wrapped += 2.0 * kPi;
  if (wrapped > kPi) wrapped -= 2.0 * kPi;
  return wrapped;
}

double AngleDifference(double a_rad, double b_rad) { return NormalizeAngle(a_rad - b_rad); }

}  // namespace fleetnav
