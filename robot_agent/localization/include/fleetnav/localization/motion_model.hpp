#pragma once

#include <cstddef>

#include "absl/status/status.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/localization/random.hpp"

namespace fleetnav::localization {

/// Odometry noise of the sampled motion models (Probabilistic Robotics Table 5.6 and the
/// omnidirectional extension of ROS amcl). Standard deviations are sqrt of quadratic forms:
/// alpha1 rotation noise from rotation, alpha2 rotation from translation, alpha3 translation
/// from translation, alpha4 translation from rotation, alpha5 strafe from translation (omni).
struct MotionModelParams {
  Kinematics kinematics = Kinematics::kDifferential;
  double alpha1 = 0.05;
  double alpha2 = 0.01;
  double alpha3 = 0.01;
  double alpha4 = 0.01;
  double alpha5 = 0.01;
  absl::Status Validate() const;
};

/// Moves every particle (structure-of-arrays, float) by the odometry motion from
/// `odom_before` to `odom_after`, sampled with the params' noise:
///  - differential: sample_motion_model_odometry (rot1, trans, rot2), Probabilistic Robotics
///    Table 5.6, with rot1 dropped below 1 cm of travel and reversing handled;
///  - omnidirectional: translation along the odometry bearing plus a strafe term (alpha5);
///  - Ackermann: a noisy arc (signed arc length and heading change, no sideways slip).
void SampleMotion(const MotionModelParams& params, const Pose2& odom_before,
                  const Pose2& odom_after, Rng& rng, float* x, float* y, float* yaw, size_t n);

}  // namespace fleetnav::localization
