#pragma once

#include <ode/ode.h>

#include <array>

#include "absl/status/status.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/robot_state.hpp"
#include "fleetnav/sim/ode_world.hpp"
#include "fleetnav/sim/robot_body.hpp"

namespace fleetnav::sim {

/// Body geometry of the physical Ackermann delivery robot that the RobotModel does not hold
/// (our choices; the capstone gives none).
struct AckermannBodyParams {
  /// Each rear motor's torque limit: it caps the tyre's push below its grip.
  double max_wheel_torque_nm = 6.0;
  /// Tyre on the yard's surface: grip across the wheel (and along it, for the driven wheels),
  /// rolling resistance of the free front wheels, and the tyre's creep under force.
  double tyre_grip_mu = 0.8;
  double rolling_resistance_mu = 0.015;
  double tyre_creep_mps_per_n = 1e-4;
  /// The suspension: each wheel a sprung contact.
  double suspension_spring_npm = 20000.0;
  double suspension_damper_nspm = 800.0;
  double ground_clearance_m = 0.05;
  double mass_box_height_m = 0.15;
  absl::Status Validate() const;
};

/// The Ackermann delivery robot in ODE (Ashesi capstone): a box chassis on four sprung wheel
/// contacts (as the mecanum platform's, so that a robot costs four contact rows, not four
/// bodies on hinges). The rear wheels are driven by velocity-controlled motors with a torque
/// limit — an electronic differential gives each the speed of its own arc — and grip along and
/// across their plane; the front wheels roll freely (rolling resistance) and grip across their
/// plane, steered to the Ackermann angles of the virtual wheel's angle, which follows its
/// command at the steering rate limit and stops at the lock (the steering joint's limits). So
/// the robot turns because its front tyres push it round — it understeers and slides when asked
/// for more than the tyres give, stops at what it drives into, and is pushed by what drives into
/// it. Speed follows the command at the acceleration limit. base_link is the rear axle's middle
/// on the floor; the chassis's centre of mass is midway between the axles. Not thread-safe;
/// owned by the simulation thread.
class AckermannRobot final : public RobotBody {
 public:
  AckermannRobot(OdeWorld* world, int robot_index, const RobotModel& model, const Pose2& start,
                 AckermannBodyParams params = {});

  const RobotModel& model() const override { return model_; }
  /// Takes a twist or an Ackermann command (clamped to the model's limits).
  absl::Status SetDrive(const DriveCommand& drive, double scale) override;
  void AfterStep(double step_s, double traction) override;
  Pose2 GroundTruthPose() const override;
  Twist2 GroundTruthVelocity() const override;  ///< of base_link, in base_link
  double UpVectorZ() const override;
  double yaw_rate_radps() const override;
  /// The rear wheels' encoders ("left", "right").
  std::vector<WheelAngle> WheelAngles() const override;
  bool physical() const override { return true; }
  std::optional<double> SteeringAngleRad() const override { return steering_rad_; }
  dBodyID chassis_body() const override { return chassis_; }

 private:
  /// Points each front wheel's grip along its steered plane and sets the rear wheels' rim
  /// speeds for the ramped speed on the current arc.
  void SetWheels();

  RobotModel model_;
  AckermannBodyParams params_;
  dBodyID chassis_ = nullptr;
  /// base_link's x in the chassis frame (the chassis's origin is its centre of mass).
  double base_x_in_chassis_m_ = 0.0;
  double chassis_z_m_ = 0.0;
  std::array<GeomTag*, 2> rear_tags_{};   ///< left, right
  std::array<GeomTag*, 2> front_tags_{};  ///< left, right
  std::array<double, 2> rear_rates_radps_{};
  std::array<double, 2> rear_angles_rad_{};
  double target_speed_mps_ = 0.0;
  double target_steering_rad_ = 0.0;
  double speed_mps_ = 0.0;  ///< ramped towards the target
  double steering_rad_ = 0.0;
};

}  // namespace fleetnav::sim
