#pragma once

#include <ode/ode.h>

#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/robot_state.hpp"
#include "fleetnav/sim/ode_world.hpp"
#include "fleetnav/sim/robot_body.hpp"

namespace fleetnav::sim {

/// Body geometry of a physical differential-drive robot that the RobotModel does not hold.
struct DiffDriveBodyParams {
  double caster_x_m = 0.71;        ///< swivel caster ahead of the drive axle (Lely: 450+260 mm)
  double caster_radius_m = 0.125;  ///< Lely: Ø 250 mm
  double wheel_width_m = 0.10;
  double wheel_mass_kg = 40.0;
  double ground_clearance_m = 0.20;
  double skirt_bottom_m = 0.08;    ///< the front bumper skirt reaches down to here
  double mass_box_height_m = 0.6;  ///< the chassis mass is spread over this height (low CoM)
  double max_wheel_torque_nm = 800.0;
};

/// A differential-drive robot as ODE bodies: a box chassis of the footprint's extent carrying
/// the model's mass, a frictionless sphere as the swivel caster, and two wheels (cylinder
/// inertia, one sphere contact on the wheel's mid-plane) on hinge joints whose velocity motors
/// have a torque limit (the Lely MFR of thesis ch. 3 by default: 1485 kg, Ø 300 mm wheels on a
/// 0.92 m track). base_link is the middle of the drive axle on the floor. Wheel angles are
/// integrated every physics step so encoders never wrap. Not thread-safe; owned by the
/// simulation thread.
class DiffDriveRobot final : public RobotBody {
 public:
  DiffDriveRobot(OdeWorld* world, int robot_index, const RobotModel& model, const Pose2& start,
                 DiffDriveBodyParams params = {});

  /// Target wheel angular velocities (rad/s), tracked by the hinge motors.
  void SetWheelSpeeds(double left_radps, double right_radps);
  /// Converts a body twist to wheel speeds (inverse of thesis eq. 3.1–3.2) and sets them.
  void SetTwist(const Twist2& twist);
  absl::Status SetDrive(const DriveCommand& drive, double scale) override;
  /// Wheel slip (traction < 1) makes the wheels turn 1/traction times as far as the ground
  /// moves under them: the encoders over-count.
  void AfterStep(double step_s, double traction) override;
  Pose2 GroundTruthPose() const override;
  Twist2 GroundTruthVelocity() const override;  ///< in base_link
  double UpVectorZ() const override;
  double left_wheel_angle_rad() const { return left_angle_rad_; }
  double right_wheel_angle_rad() const { return right_angle_rad_; }
  double yaw_rate_radps() const override;
  const RobotModel& model() const override { return model_; }
  std::vector<WheelAngle> WheelAngles() const override {
    return {{"left", left_angle_rad_}, {"right", right_angle_rad_}};
  }
  bool physical() const override { return true; }
  dBodyID chassis_body() const override { return chassis_; }

 private:
  dBodyID CreateWheel(double y_m, const Pose2& start, double axle_z_m);

  RobotModel model_;
  DiffDriveBodyParams params_;
  double chassis_offset_x_m_ = 0.0;  ///< chassis centre ahead of base_link
  double chassis_z_m_ = 0.0;
  dBodyID chassis_ = nullptr;
  dBodyID left_wheel_ = nullptr;
  dBodyID right_wheel_ = nullptr;
  dJointID left_hinge_ = nullptr;
  dJointID right_hinge_ = nullptr;
  double left_angle_rad_ = 0.0;
  double right_angle_rad_ = 0.0;
  OdeWorld* world_;
  int robot_index_;
};

}  // namespace fleetnav::sim
