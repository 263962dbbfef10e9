#pragma once

#include "absl/status/statusor.h"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/sim/robot_body.hpp"

namespace fleetnav::sim {

/// What an Ackermann robot's drive is asked for: rear-axle speed and the steering angle of
/// the bicycle model's virtual front wheel, within the model's limits.
struct AckermannTarget {
  double speed_mps = 0.0;
  double steering_rad = 0.0;
};

/// Turns a drive command for an Ackermann robot into its target: a twist (v, ω) steers
/// atan(ω L / v) (kept at `previous_steering_rad` while v is about 0), an AckermannDrive is
/// taken as it is; the speed (times `scale`, the slow-down fault) and the angle are clamped to
/// the model's limits. InvalidArgument for wheel speeds or values that are not finite.
absl::StatusOr<AckermannTarget> AckermannTargetOf(const RobotModel& model,
                                                  const DriveCommand& drive, double scale,
                                                  double previous_steering_rad);

/// The steering angles of the left and right front wheels for the virtual wheel's angle δ
/// (Ackermann geometry: both wheels' axles meet the rear axle's line at the same point,
/// tan δ_side = L tan δ / (L ∓ (t/2) tan δ)).
struct FrontWheelAngles {
  double left_rad = 0.0;
  double right_rad = 0.0;
};
FrontWheelAngles AckermannFrontWheelAngles(double steering_rad, double wheelbase_m, double track_m);

}  // namespace fleetnav::sim
