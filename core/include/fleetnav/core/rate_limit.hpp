#pragma once

#include <algorithm>

namespace fleetnav {

/// `current` moved towards `target` by at most `max_step` (a rate limit applied over one
/// step: a speed ramped with its acceleration limit, a steering angle at its rate limit).
inline double StepTowards(double current, double target, double max_step) {
  return current + std::clamp(target - current, -max_step, max_step);
}

}  // namespace fleetnav
